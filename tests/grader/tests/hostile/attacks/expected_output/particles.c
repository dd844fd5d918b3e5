/* Attack: the C task's program prints the expected output instead of computing it. The old
 * grader ran the program in the folder where the expected output lay; this looks for it there,
 * in every folder above, in the temporary folders and in the home folder, and prints the first
 * file whose name says "expected". The judge computes the expected output in its own folder. */
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int print_expected(const char* folder) {
  DIR* listing = opendir(folder);
  if (listing == NULL) return 0;
  struct dirent* entry;
  int printed = 0;
  while (!printed && (entry = readdir(listing)) != NULL) {
    if (strstr(entry->d_name, "expected") == NULL) continue;
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", folder, entry->d_name);
    FILE* file = fopen(path, "r");
    if (file == NULL) continue;
    int c;
    while ((c = fgetc(file)) != EOF) putchar(c);
    fclose(file);
    printed = 1;
  }
  closedir(listing);
  return printed;
}

int main(void) {
  const char* home = getenv("HOME");
  const char* folders[] = {".", "..", "../..", "../../..", "/tmp", "/var/tmp", home ? home : "."};
  for (size_t i = 0; i < sizeof folders / sizeof folders[0]; ++i) {
    if (print_expected(folders[i])) return 0;
  }
  printf("0.000000, 0.000000, 0, 0\n");
  return 0;
}
