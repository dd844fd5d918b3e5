/* Task particles (the C track): the "Collisions" program.
 *
 *     particles FILE END_TIME
 *
 * N equal discs of radius R move in the box [0, Lx] x [0, Ly] (walls at x = 0, x = Lx, y = 0,
 * y = Ly). The file: line 1 N, line 2 R, line 3 Lx Ly, then N lines "x y u v" (position and
 * velocity). Process every collision up to END_TIME in time order (one at END_TIME exactly
 * included), then move every particle to END_TIME; the program prints one line per particle,
 * in the file's order:  x, y, wall collisions, particle collisions.
 *
 * Reading the file, printing and main() are written for you below. Write simulate(), and the
 * helpers it needs, the assignment's way:
 *
 *   1. An array of all N(N+1)/2 potential collisions (the Collision struct below): one per
 *      particle for the wall it reaches first, one per pair (i, j) with i < j. Store absolute
 *      times (time since the start), so that entries nobody touched stay valid.
 *   2. Wall: the centre's limits are R and L - R. Along x, the time from now is
 *      (R - x) / u for u < 0, (Lx - R - x) / u for u > 0, never for u == 0; the same along y.
 *      Keep the earlier of the two (on a tie take x; y then follows at the same instant).
 *      A particle rounding a hair beyond its limit just after a bounce gives 0, not a time in
 *      the past.
 *   3. Pair: with dr and dv the differences of positions and velocities, they touch when
 *      |dr + dv t| = 2R: a t^2 + 2 b t + c = 0 with a = dv.dv, b = dr.dv, c = dr.dr - (2R)^2.
 *      Only if they approach (b < 0) and the discriminant b^2 - a c >= 0 do they meet, at the
 *      SMALLER root t = (-b - sqrt(b^2 - a c)) / a. Otherwise the time is INFINITY.
 *   4. Sort the array by time with an insertion sort (each entry moves left past the later
 *      ones). Then loop while the first entry happens no later than END_TIME:
 *        - move EVERY particle to the time of that collision (x += u dt, y += v dt);
 *        - a wall: reverse the velocity component normal to it, count one wall collision;
 *          two particles: they exchange their whole velocities (u and v), count one particle
 *          collision for each;
 *        - recompute every entry that involves EITHER particle of the collision (its wall and
 *          all its pairs: their velocities changed), and sort again.
 *   5. Finally move every particle from the last collision to END_TIME.
 *
 * Build and test:  ./build.sh test -L particles   (examples with their expected outputs are in
 * tests/particles/examples/: run build/tasks/tasks/particles FILE END_TIME on one of them and
 * compare with its .expected file).
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

/* Processes every collision up to end_time, then moves every particle to end_time
 * (steps 1-5 above). Replace the two lines of the body with your code. */
static void simulate(Box *box, double end_time) {
  (void)box, (void)end_time;
  fprintf(stderr, "task 10 (particles) is not implemented yet: write it in tasks/particles.c, then run its "
                  "tests with: ./build.sh test -L particles\n");
  exit(1);
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
