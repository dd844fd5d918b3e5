/* Task particles (the C track), reference solution: the "Collisions" program.
 *
 *     particles FILE END_TIME
 *
 * N equal discs of radius R move in the box [0, Lx] x [0, Ly]. Every collision up to END_TIME is
 * processed in time order; then every particle is moved to END_TIME and one line per particle
 * is printed: x, y, wall collisions, particle collisions.
 *
 * The method: an array of all N(N+1)/2 potential collisions, one per particle for the wall it
 * reaches first and one per pair, kept sorted by time with an insertion sort. The first entry
 * is the next collision. After processing it, the entries of the particles involved are
 * recomputed (nothing else changed) and the array is sorted again, which is quick because it is
 * almost sorted.
 *
 * Times in the array are absolute (time since the start), so that the entries nobody touched
 * stay valid while the clock moves on.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

typedef struct {
  double x, y; /* position */
  double u, v; /* velocity */
  int wall_collisions;
  int particle_collisions;
} Particle;

/* Which wall a particle meets: the pair x = R / x = Lx - R, or y = R / y = Ly - R. */
typedef enum { WALL_X, WALL_Y } WallAxis;

/* A potential collision: particle i with particle j, or with a wall when j == WALL. */
enum { WALL = -1 };
typedef struct {
  double time; /* absolute; INFINITY when it never happens */
  int i, j;
  WallAxis axis; /* for a wall */
} Collision;

typedef struct {
  int n;
  double radius, lx, ly;
  Particle *particles;
} Box;

/* Prints a one-line error and exits with status 2 (bad input). */
static void fail(const char *file, const char *what) {
  fprintf(stderr, "particles: %s: %s\n", file, what);
  exit(2);
}

/* Reads the input file; exits with a message naming the problem if it is malformed. */
static Box read_box(const char *file_name) {
  Box box = {0, 0, 0, 0, NULL};
  FILE *file = fopen(file_name, "r");
  if (file == NULL) fail(file_name, "cannot open it; check the file name");
  if (fscanf(file, "%d", &box.n) != 1 || box.n < 0) fail(file_name, "line 1 must hold N, a whole number >= 0");
  if (fscanf(file, "%lf", &box.radius) != 1 || !(box.radius > 0)) fail(file_name, "line 2 must hold the radius R > 0");
  if (fscanf(file, "%lf %lf", &box.lx, &box.ly) != 2 || !(box.lx > 0) || !(box.ly > 0)) {
    fail(file_name, "line 3 must hold the box lengths Lx > 0 and Ly > 0");
  }
  box.particles = calloc((size_t)box.n + 1, sizeof(Particle));
  if (box.particles == NULL) fail(file_name, "not enough memory for N particles");
  for (int k = 0; k < box.n; ++k) {
    Particle *p = &box.particles[k];
    if (fscanf(file, "%lf %lf %lf %lf", &p->x, &p->y, &p->u, &p->v) != 4) {
      fail(file_name, "each of the N lines after line 3 must hold x y u v");
    }
  }
  fclose(file);
  return box;
}

/* Time from now until a particle at `position` moving with `speed` reaches the wall at `low`
 * or `high` (the centre's limits, R and L - R): (low - position) / speed when moving down,
 * (high - position) / speed when moving up. Rounding can leave a particle a hair beyond its
 * limit just after a bounce: that gives 0, never a time in the past. */
static double wall_time(double position, double speed, double low, double high) {
  double t;
  if (speed > 0) {
    t = (high - position) / speed;
  } else if (speed < 0) {
    t = (low - position) / speed;
  } else {
    return INFINITY;
  }
  return t > 0 ? t : 0;
}

/* The earlier of particle i's two walls; on a tie (a corner) x first, then y at the same
 * instant when the entry is recomputed: two wall collisions. */
static Collision wall_collision(const Box *box, int i, double now) {
  const Particle *p = &box->particles[i];
  double tx = wall_time(p->x, p->u, box->radius, box->lx - box->radius);
  double ty = wall_time(p->y, p->v, box->radius, box->ly - box->radius);
  Collision c = {now + tx, i, WALL, WALL_X};
  if (ty < tx) {
    c.time = now + ty;
    c.axis = WALL_Y;
  }
  return c;
}

/* When particles i and j touch: |dr + dv t| = 2R, with dr and dv the differences of their
 * positions and velocities. That is a t^2 + 2 b t + c = 0 with a = dv.dv, b = dr.dv,
 * c = dr.dr - (2R)^2. They can meet only if they approach (b < 0) and the discriminant
 * b^2 - a c is not negative; they touch first at the smaller root. */
static Collision pair_collision(const Box *box, int i, int j, double now) {
  const Particle *p = &box->particles[i];
  const Particle *q = &box->particles[j];
  double dx = q->x - p->x, dy = q->y - p->y;
  double du = q->u - p->u, dv = q->v - p->v;
  double a = du * du + dv * dv;
  double b = dx * du + dy * dv;
  double c = dx * dx + dy * dy - 4 * box->radius * box->radius;
  double discriminant = b * b - a * c;
  Collision collision = {INFINITY, i, j, WALL_X};
  if (b < 0 && discriminant >= 0) {
    double t = (-b - sqrt(discriminant)) / a;
    collision.time = now + (t > 0 ? t : 0);
  }
  return collision;
}

static int involves(const Collision *c, int particle) { return c->i == particle || c->j == particle; }

/* Sorts by time, earliest first. Insertion sort: each entry moves left past the later ones.
 * Stable, and quick on an array that is almost sorted, as it is after each update. */
static void insertion_sort(Collision *collisions, long count) {
  for (long k = 1; k < count; ++k) {
    Collision current = collisions[k];
    long m = k;
    while (m > 0 && collisions[m - 1].time > current.time) {
      collisions[m] = collisions[m - 1];
      --m;
    }
    collisions[m] = current;
  }
}

/* Moves every particle along its velocity for dt. */
static void advance(Box *box, double dt) {
  for (int k = 0; k < box->n; ++k) {
    box->particles[k].x += box->particles[k].u * dt;
    box->particles[k].y += box->particles[k].v * dt;
  }
}

/* Processes every collision up to end_time (one at end_time exactly included), then moves
 * every particle to end_time. */
static void simulate(Box *box, double end_time) {
  long count = (long)box->n * (box->n + 1) / 2;
  Collision *collisions = calloc((size_t)count + 1, sizeof(Collision));
  if (collisions == NULL) {
    fprintf(stderr, "particles: not enough memory for N(N+1)/2 collisions\n");
    exit(2);
  }
  long k = 0;
  for (int i = 0; i < box->n; ++i) collisions[k++] = wall_collision(box, i, 0);
  for (int i = 0; i < box->n; ++i) {
    for (int j = i + 1; j < box->n; ++j) collisions[k++] = pair_collision(box, i, j, 0);
  }
  insertion_sort(collisions, count);

  double now = 0;
  while (count > 0 && collisions[0].time <= end_time) {
    Collision next = collisions[0];
    advance(box, next.time - now);
    now = next.time;
    Particle *p = &box->particles[next.i];
    int partner = next.i; /* the other particle involved; the same one for a wall */
    if (next.j == WALL) {
      if (next.axis == WALL_X) {
        p->u = -p->u;
      } else {
        p->v = -p->v;
      }
      p->wall_collisions++;
    } else {
      Particle *q = &box->particles[next.j];
      double u = p->u, v = p->v;
      p->u = q->u;
      p->v = q->v;
      q->u = u;
      q->v = v;
      p->particle_collisions++;
      q->particle_collisions++;
      partner = next.j;
    }
    /* Both particles move differently now: every entry of either is out of date. */
    for (long e = 0; e < count; ++e) {
      Collision *c = &collisions[e];
      if (involves(c, next.i) || involves(c, partner)) {
        *c = c->j == WALL ? wall_collision(box, c->i, now) : pair_collision(box, c->i, c->j, now);
      }
    }
    insertion_sort(collisions, count);
  }
  advance(box, end_time - now);
  free(collisions);
}

int main(int argc, char **argv) {
  if (argc != 3) {
    fprintf(stderr, "usage: particles FILE END_TIME (for example: particles box.txt 10)\n");
    return 2;
  }
  char *end = NULL;
  double end_time = strtod(argv[2], &end);
  if (end == argv[2] || *end != '\0' || !(end_time >= 0) || isinf(end_time)) {
    fprintf(stderr, "particles: END_TIME must be a number >= 0, got '%s'\n", argv[2]);
    return 2;
  }
  Box box = read_box(argv[1]);
  simulate(&box, end_time);
  for (int k = 0; k < box.n; ++k) {
    const Particle *p = &box.particles[k];
    printf("%.6f, %.6f, %d, %d\n", p->x, p->y, p->wall_collisions, p->particle_collisions);
  }
  free(box.particles);
  return 0;
}
