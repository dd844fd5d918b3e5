/* Stand-in for a submitted program task (a C task) that does not compile: it says "not
 * implemented yet" as the stub does, so the task's tests fail with that message and the
 * other tasks are graded normally. BILLIARD_STUB_NUMBER and BILLIARD_STUB_NAME name the task. */
#include <stdio.h>

int main(void) {
  fprintf(stderr, "task %d (%s) is not implemented yet: write it in tasks/%s.c\n", BILLIARD_STUB_NUMBER,
          BILLIARD_STUB_NAME, BILLIARD_STUB_NAME);
  return 1;
}
