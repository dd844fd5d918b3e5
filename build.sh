#!/usr/bin/env bash
# The project's commands (see README.md; run and test are the quick start's two):
#   ./build.sh run  [TABLE_RADIUS CIRCLE_RADIUS N] [billiard options]   build, then run `billiard`
#                   (in a course of the C track alone: [FILE END_TIME], run `particles`)
#   ./build.sh test [ctest options]                                     build, then run every test
#   ./build.sh python                       build the Python module `billiard` and make Debian's
#                                           /usr/bin/python3 import it (for the notebooks)
#   ./build.sh grade [grader options]       grade tasks/ per task, as the graders do (--help)
#   ./build.sh bench [benchmark options]    build, then run the engine's benchmark (--help)
#   ./build.sh setup                        only install the missing Debian packages (the graders'
#                                           setup; root or sudo)
# Each first installs the Debian packages the build needs (only the missing ones), then configure
# and build with CMake. `test -L LABEL` builds only what those tests need, and the labels the
# full run leaves out (stress, platforms) run when named: ./build.sh test -L stress. Set
# BILLIARD_PRESET to use another preset from CMakePresets.json (default: "release", the
# reference solutions, where solutions/ exists; else "tasks").
set -euo pipefail
cd "$(dirname "$0")"
if [ -z "${BILLIARD_PRESET:-}" ]; then
  if [ -d solutions ]; then BILLIARD_PRESET=release; else BILLIARD_PRESET=tasks; fi
fi

usage() {
  awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"
}

# Debian packages, by what needs them. Names are apt-get names: there is no PyPI here.
# The command, its tests and the grader need these (run, grade, setup):
packages=(
  cmake ninja-build g++ gcc      # the build (gcc: the C track's task, tasks/particles.c)
  libeigen3-dev                  # vectors and matrices
  libgtest-dev                   # the graded test suites
  libpugixml-dev                 # the XML under the graded suites' SVG reader
  python3                        # the grader (tests/grader/grade.py), run as /usr/bin/python3
  python3-yaml                   # the instructors' packaging tests read YAML (GitHub workflows)
  make                           # the Autolab package's test runs its Makefile
)
# The Python module and the notebooks need these as well (test, python):
python_packages=(
  pybind11-dev python3-dev       # the module `billiard` for Debian's /usr/bin/python3
  python3-numpy python3-matplotlib python3-pil  # arrays, figures, GIF animations
  ffmpeg                         # MP4 animations
  python3-pytest                 # the module's tests
  jupyter-nbconvert python3-nbclient python3-ipykernel  # running the notebooks headless
  python3-dask python3-distributed  # billiard.sweep: ensembles of runs on worker processes or a cluster
)
# The tests need these as well (test):
test_packages=(
  ccache                         # the tests build the sources again elsewhere (the grader's build)
)

# install_missing_packages [PACKAGE...]: the core packages above and the given ones.
install_missing_packages() {
  local missing=() p
  for p in "${packages[@]}" "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q '^install ok installed$' || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  local sudo=()
  if [ "$(id -u)" -ne 0 ]; then
    if command -v sudo >/dev/null; then sudo=(sudo); else
      echo "build.sh: missing Debian packages: ${missing[*]}; install them as root with: apt-get install ${missing[*]}" >&2
      exit 2
    fi
  fi
  echo "build.sh: installing Debian packages: ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  "${sudo[@]}" apt-get update -qq
  "${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
}

# configure: CMake's configure step, with configure_options (below) on top of the preset's.
configure() {
  cmake --preset "$BILLIARD_PRESET" "${configure_options[@]}" >/dev/null
}
# build_targets [TARGET...]: build the given targets, or everything.
build_targets() {
  cmake --build --preset "$BILLIARD_PRESET" ${1:+--target "$@"}
}
# build [TARGET...]: configure, then build the given targets, or everything.
build() {
  configure
  build_targets "$@"
}
configure_options=()

# Makes Debian's /usr/bin/python3 import the module `billiard` built here, from any folder: a
# .pth file in the user's site-packages names the build's python/ folder (no pip, no PyPI).
register_python_module() {
  local site
  site=$(/usr/bin/python3 -c 'import site; print(site.getusersitepackages())')
  mkdir -p "$site"
  echo "$PWD/build/$BILLIARD_PRESET/python" > "$site/billiard.pth"
  echo "build.sh: /usr/bin/python3 imports billiard from build/$BILLIARD_PRESET/python (via $site/billiard.pth)"
}

# read_label_options [ctest options]: sets `labels` to the labels the options select (-L LABEL,
# --label-regex LABEL) and `label_exclude` to 1 when they exclude labels themselves (-LE).
read_label_options() {
  labels=()
  label_exclude=0
  while [ $# -gt 0 ]; do
    case "$1" in
      -L|--label-regex) [ $# -gt 1 ] && labels+=("$2"); shift ;;
      --label-regex=*) labels+=("${1#--label-regex=}") ;;
      -LE|--label-exclude|--label-exclude=*) label_exclude=1 ;;
    esac
    shift
  done
}

# targets_for_labels: sets `targets` to what the tests with those labels run, so that a
# student's `./build.sh test -L propagate` builds only that task's suite. Empty (build
# everything) when no label is selected, or one is a pattern or a label whose tests have not
# declared what they need (build/<preset>/test_labels.txt).
targets_for_labels() {
  targets=()
  local list=build/$BILLIARD_PRESET/test_labels.txt label
  [ ${#labels[@]} -gt 0 ] && [ -f "$list" ] || return 0
  for label in "${labels[@]}"; do
    if ! grep -qxF -- "$label" "$list"; then targets=(); return 0; fi
    targets+=("tests_$label")
  done
}

# excluded_labels_named: sets `include_excluded` to "-LE ^$" (exclude nothing) when a selected
# label is one the test presets leave out (stress, platforms) and the options exclude nothing
# themselves, so that `./build.sh test -L stress` runs those tests.
excluded_labels_named() {
  include_excluded=()
  local label
  [ "$label_exclude" = 1 ] && return 0
  for label in "${labels[@]}"; do
    [[ "$label" =~ stress|platforms ]] && include_excluded=(-LE '^$')
  done
  return 0
}

# The fuzz tests' counts (cases tried, how each ended), from the log of the test run just done.
print_fuzz_counts() {
  local log=build/$BILLIARD_PRESET/Testing/Temporary/LastTest.log counts
  [ -f "$log" ] || return 0
  counts=$(grep -ohE '(cli fuzz: [0-9]|api fuzz: [0-9]|python [A-Za-z]+ fuzz \(|find_task_files: [0-9]|archive bombs: |stage_submission: [0-9]).*' "$log" || true)
  [ -n "$counts" ] && printf '\nFuzz tests run:\n%s\n' "$counts"
  return 0
}

command=${1:-}
[ $# -gt 0 ] && shift
case "$command" in
  run)
    install_missing_packages
    configure
    dir=build/$BILLIARD_PRESET
    if ninja -C "$dir" -t query billiard >/dev/null 2>&1; then
      build_targets billiard
      if [ $# -eq 0 ]; then set -- 10 1 10; fi
      exec "$dir/billiard" --output build/output "$@"
    fi
    # The C track alone (every C++ task off in tests/grader/course.txt) has no `billiard`: run
    # the course's C program instead, by default on the example the README shows.
    course=$(sed -n 's/^BILLIARD_COURSE:[A-Z]*=//p' "$dir/CMakeCache.txt")
    build_targets "billiard_${course}_particles"
    if [ $# -eq 0 ]; then set -- tests/particles/examples/three.txt 4; fi
    exec "$dir/$course/particles" "$@"
    ;;
  test)
    install_missing_packages "${python_packages[@]}" "${test_packages[@]}"
    configure_options=(-DBILLIARD_PYTHON=ON)  # the module and notebooks are tested: never skip them
    configure
    read_label_options "$@"
    targets_for_labels
    excluded_labels_named
    build_targets "${targets[@]}"
    register_python_module >/dev/null
    status=0
    results=$PWD/build/$BILLIARD_PRESET/Testing/results.xml
    rm -f "$results"
    ctest --preset "$BILLIARD_PRESET" --output-junit "$results" "$@" "${include_excluded[@]}" || status=$?
    print_fuzz_counts
    # Where the tasks stand and what to do next, in a few lines (tests/grader/progress.py).
    [ -f "$results" ] && /usr/bin/python3 tests/grader/progress.py "$results"
    exit "$status"
    ;;
  python)
    install_missing_packages "${python_packages[@]}"
    configure_options=(-DBILLIARD_PYTHON=ON)
    build billiard_python
    register_python_module
    ;;
  bench)
    install_missing_packages
    build billiard_bench
    exec "build/$BILLIARD_PRESET/lib/bench/billiard_bench" "$@"
    ;;
  grade)
    install_missing_packages
    exec /usr/bin/python3 tests/grader/grade.py "$@"
    ;;
  setup)
    install_missing_packages
    ;;
  -h|--help|help)
    usage
    ;;
  *)
    echo "build.sh: unknown command '${command}'; use './build.sh run' or './build.sh test' (see ./build.sh --help)" >&2
    exit 2
    ;;
esac
