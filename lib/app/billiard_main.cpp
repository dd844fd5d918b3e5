#include "billiard/course.hpp"
int main() { return 0; }
