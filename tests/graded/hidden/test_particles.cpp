// Hidden tests of task particles (instructors only; not in the student release): files with more
// particles, each checked to give the same output, to %.6f, from the project's particles command
// and from the assignment's method (solutions/particles.c), and the edge cases. The hints stay
// general: students see these results only as passed or failed.
#include "../particles_support.hpp"
#include "support/graded.hpp"

namespace {

using particles_grading::expect_same_output;

constexpr const char* kGeneralHint =
    "compare with the visible tests: the first of them that fails names the step to fix";

GRADED_TEST(ParticlesHidden, EmptyBoxPrintsNothing, 1, hidden) {
  expect_same_output("empty", "0\n0.5\n10 6\n", "5", kGeneralHint);
}

GRADED_TEST(ParticlesHidden, EndTimeZeroLeavesEveryParticle, 1, hidden) {
  expect_same_output("end_zero", "2\n0.5\n10 6\n2 3 1 0\n5 3 -1 0\n", "0", kGeneralHint);
}

GRADED_TEST(ParticlesHidden, ParticleAtRestIsHitAndMoves, 1, hidden) {
  expect_same_output("at_rest", "3\n0.5\n10 6\n2 3 1 0\n5 3 0 0\n8 3.2 0 0\n", "9", kGeneralHint);
}

// 8 particles to END_TIME 15: 8 wall and 8 particle collisions.
GRADED_TEST(ParticlesHidden, Random1With8Particles, 2, hidden) {
  expect_same_output("random_1",
                     "8\n"
                     "0.5\n"
                     "20 15\n"
                     "11.241 9.176 -0.517 -0.13\n"
                     "19.162 11.383 -0.258 0.395\n"
                     "14.779 11.473 -0.961 0.503\n"
                     "6.685 9.128 -0.119 -0.074\n"
                     "13.866 2.643 -0.172 -0.603\n"
                     "8.825 9.025 0.849 0.476\n"
                     "19.194 4.769 -0.855 -0.761\n"
                     "13.285 12.957 0.676 0.078\n",
                     "15", kGeneralHint);
}

// 12 particles to END_TIME 15: 22 wall and 16 particle collisions.
GRADED_TEST(ParticlesHidden, Random2With12Particles, 2, hidden) {
  expect_same_output("random_2",
                     "12\n"
                     "0.5\n"
                     "15 10\n"
                     "8.154 9.283 0.565 0.77\n"
                     "11.378 0.829 -0.404 -0.449\n"
                     "5.506 3.839 -0.341 0.568\n"
                     "11.487 9.184 0.922 -0.068\n"
                     "9.82 9.415 -0.593 0.668\n"
                     "11.915 6.606 0.297 0.69\n"
                     "7.373 7.164 0.912 -0.08\n"
                     "8.538 0.619 0.686 0.331\n"
                     "2.255 3.878 0.764 0.418\n"
                     "5.393 5.625 -0.212 0.59\n"
                     "13.135 2.036 -0.687 -0.228\n"
                     "11.36 2.9 0.361 -0.655\n",
                     "15", kGeneralHint);
}

// 12 particles to END_TIME 15: 15 wall and 18 particle collisions.
GRADED_TEST(ParticlesHidden, Random3With12Particles, 2, hidden) {
  expect_same_output("random_3",
                     "12\n"
                     "0.5\n"
                     "12 10\n"
                     "3.347 1.063 0.373 -0.2\n"
                     "3.197 9.414 -0.119 0.575\n"
                     "10.664 3.346 0.308 0.59\n"
                     "10.104 6.888 0.228 -0.047\n"
                     "7.759 7.85 -0.215 -0.88\n"
                     "0.667 3.292 0.448 -0.25\n"
                     "7.449 5.804 -0.821 0.207\n"
                     "9.227 9.282 0.281 -0.47\n"
                     "2.029 2.324 0.791 0.106\n"
                     "1.722 6.749 0.501 -0.58\n"
                     "11.003 9.237 0.279 -0.699\n"
                     "5.756 7.888 0.011 0.475\n",
                     "15", kGeneralHint);
}

// 16 particles to END_TIME 15: 28 wall and 32 particle collisions.
GRADED_TEST(ParticlesHidden, Random4With16Particles, 2, hidden) {
  expect_same_output("random_4",
                     "16\n"
                     "0.5\n"
                     "12 10\n"
                     "8.56 7.722 0.491 0.003\n"
                     "10.324 2.986 -0.316 -0.278\n"
                     "2.193 6.225 -0.789 -0.821\n"
                     "4.211 5.269 -0.98 -0.533\n"
                     "1.154 9.029 -0.49 0.193\n"
                     "2.859 4.493 -0.01 -0.973\n"
                     "11.295 1.964 -0.878 -0.811\n"
                     "1.405 0.924 0.051 -0.301\n"
                     "6.097 4.373 0.293 -0.077\n"
                     "7.637 3.999 -0.052 -0.891\n"
                     "10.552 6.397 0.291 -0.294\n"
                     "5.228 8.25 0.326 -0.027\n"
                     "10.086 7.722 -0.877 0.59\n"
                     "5.765 2.73 0.63 0.581\n"
                     "4.424 6.362 -0.038 -0.978\n"
                     "4.258 7.65 0.52 0.326\n",
                     "15", kGeneralHint);
}

// 16 particles to END_TIME 12.5: 21 wall and 20 particle collisions.
GRADED_TEST(ParticlesHidden, Random5With16Particles, 2, hidden) {
  expect_same_output("random_5",
                     "16\n"
                     "0.5\n"
                     "20 8\n"
                     "6.142 1.557 -0.197 -0.735\n"
                     "3.582 4.334 0.942 -0.389\n"
                     "12.859 3.224 0.53 0.165\n"
                     "4.094 7.292 0.423 -0.201\n"
                     "11.621 0.74 -0.322 0.351\n"
                     "17.185 6.239 0.682 0.878\n"
                     "7.683 0.645 -0.689 0.999\n"
                     "1.1 6.987 -0.651 0.52\n"
                     "6.268 3.88 0.1 0.286\n"
                     "2.622 5.451 -0.163 -0.277\n"
                     "15.423 3.404 0.91 0.493\n"
                     "8.728 0.781 0.77 0.366\n"
                     "9.309 5.158 -0.457 0.939\n"
                     "4.399 2.28 0.583 0.668\n"
                     "11.513 4.17 0.206 0.706\n"
                     "1.48 0.934 0.94 0.67\n",
                     "12.5", kGeneralHint);
}

// 12 particles to END_TIME 12.5: 13 wall and 10 particle collisions.
GRADED_TEST(ParticlesHidden, Random6With12Particles, 2, hidden) {
  expect_same_output("random_6",
                     "12\n"
                     "0.5\n"
                     "12 15\n"
                     "3.608 6.864 0.212 0.72\n"
                     "10.994 0.846 0.416 -0.569\n"
                     "3.291 1.491 0.226 0.265\n"
                     "9.93 5.47 0.459 -0.283\n"
                     "0.755 10.893 -0.173 -0.828\n"
                     "8.246 13.468 0.518 0.262\n"
                     "10.421 13.214 0.776 -0.896\n"
                     "10.145 1.758 0.657 0.806\n"
                     "2.703 2.392 -0.834 -0.299\n"
                     "4.834 10.142 0.093 0.976\n"
                     "6.497 10.128 0.245 0.25\n"
                     "9.796 14.166 0.563 -0.212\n",
                     "12.5", kGeneralHint);
}

}  // namespace
