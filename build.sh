#!/usr/bin/env bash
# The project's commands (see README.md; run and test are the quick start's two):
#   ./build.sh run  [TABLE_RADIUS CIRCLE_RADIUS N] [billiard options]   build, then run `billiard`
#                   (in a course of the C track alone: [FILE END_TIME], run `particles`)
#   ./build.sh test [ctest options]                                     build, then run the tests
#                   (in a student's copy, where there is no solutions/: their tasks' graded suites
#                   and the commands' tests; every other label runs when named: -L engine)
#   ./build.sh python                       build the Python module `billiard` and make Debian's
#                                           /usr/bin/python3 import it (for the notebooks)
#   ./build.sh grade [grader options]       grade tasks/ per task, as the graders do (--help)
# instructors
#                                           with --class DIR, a whole class (also sets up Dask
#                                           and the copy finder, Dolos, from npm)
# /instructors
#   ./build.sh bench [benchmark options]    build, then run the engine's benchmark (--help)
#   ./build.sh setup                        only install the missing packages (the graders'
#                                           setup; root or sudo)
# Each first installs the system packages the build needs (only the missing ones), then configure
# and build with CMake. `test -L LABEL` builds only what those tests need, and the labels the
# full run leaves out (stress, platforms, contributing) run when named: ./build.sh test -L stress. Set
# BILLIARD_PRESET to use another preset from CMakePresets.json (default: "release", the
# reference solutions, where solutions/ exists; else "tasks").
set -euo pipefail
cd "$(dirname "$0")"
if [ -z "${BILLIARD_PRESET:-}" ]; then
  if [ -d solutions ]; then BILLIARD_PRESET=release; else BILLIARD_PRESET=tasks; fi
fi

usage() {
  awk 'NR > 1 && /^# \/?instructors$/ { next } NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"
}

# Debian's and Ubuntu's packages, by what needs them (apt names: there is no PyPI here; the
# supported systems are in README.md). An entry is a package that its list's commands need, or
# PACKAGE:FEATURE, a package that only FEATURE needs: on a system without it, build.sh says in
# one line which feature is missing and sets up the rest.
# The command, its tests and the grader need these (run, grade, setup):
packages=(
  cmake ninja-build g++ gcc      # the build (gcc: the C track's task, tasks/particles.c)
  libeigen3-dev                  # vectors and matrices
  libgtest-dev                   # the graded test suites
  libpugixml-dev                 # the XML under the graded suites' SVG reader
  libseccomp-dev                 # the grader's cells: what submitted code may not do
  python3                        # the grader (tests/grader/grade.py), run as /usr/bin/python3
  make                           # the Autolab package's test runs its Makefile
)
# The Python module and the notebooks need these as well (test, python):
python_packages=(
  pybind11-dev python3-dev python3-numpy  # the module `billiard` for /usr/bin/python3
  python3-pytest                 # the module's tests
  "python3-matplotlib:figures and animations (billiard.plot, the notebooks)"
  "python3-pil:GIF animations"
  "ffmpeg:MP4 animations"
  "jupyter-nbconvert:running the notebooks headless" "python3-nbclient:running the notebooks headless"
  "python3-ipykernel:running the notebooks headless"
  "python3-dask:ensembles of runs on worker processes or a cluster (billiard.sweep)"
  "python3-distributed:ensembles of runs on worker processes or a cluster (billiard.sweep)"
  "python3-gsd:GSD trajectories (billiard.write_trajectory, HOOMD-blue's format, read by OVITO)"
  "python3-pip:installing the package like a library (pip install . into a venv)"
  "python3-venv:installing the package like a library (pip install . into a venv)"
)
# Grading a whole class needs these as well (grade --class; test, with the grader's labels); a
# student's copy, which has no class grader, has none.
class_packages=()
install_copy_finder() { :; }
# instructors
# (tests/grader/package.py leaves each block from "# instructors" to "# /instructors" out of
# the student release.)
class_packages=(
  "python3-distributed:grading a class on a Dask cluster (without it, on this machine's processors)"
  "python3-matplotlib:the class report's figures"
  "nodejs:the class report's near-copies (the copy finder, Dolos, runs on Node.js)"
  "npm:the class report's near-copies (the copy finder, Dolos, comes from npm)"
)
# /instructors
# The grader's tests need these as well (test, with every test or the labels grader, packages,
# platforms, contributing):
test_packages=(
  "${class_packages[@]}"
  ccache                         # the tests build the sources again elsewhere (the grader's build)
  "chromium:the class report's test in a real browser, headless"
  "python3-yaml:the packaging tests' reading of GitHub workflows"
  "g++-11:the check that the code builds with GCC 11, Ubuntu 22.04's (Debian 12 has it)"
)

# system_name: this system as /etc/os-release names it ("Debian GNU/Linux 13 (trixie)").
system_name() {
  (. /etc/os-release 2>/dev/null && echo "${PRETTY_NAME:-this system}") || echo "this system"
}

# has_candidate PACKAGE: apt can install it here (it is in this system's package lists). (grep
# reads all of apt-cache's output: with -q it could stop early, and pipefail see apt-cache's SIGPIPE.)
has_candidate() {
  apt-cache policy "$1" 2>/dev/null | grep '^ *Candidate: [^(]' >/dev/null
}

# installed PACKAGE: the package is installed, or, for Node.js and npm, their commands are there
# (NodeSource's nodejs, say, which brings its own npm and conflicts with the system's npm).
installed() {
  case "$1" in
    nodejs) command -v node >/dev/null && return 0 ;;
    npm) command -v npm >/dev/null && return 0 ;;
  esac
  dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep '^install ok installed$' >/dev/null
}

# install_missing_packages [ENTRY...]: the core packages above and the given entries (a package,
# or PACKAGE:FEATURE), the missing ones only. A package this system has none of stops the set-up
# when its list needs it, and costs only its feature otherwise: one line each says which.
install_missing_packages() {
  local entry name missing=() absent=() unavailable=() sudo=()
  declare -A feature=() required=() seen=()
  for entry in "${packages[@]}" "$@"; do
    name=${entry%%:*}
    if [[ $entry == *:* ]]; then
      feature[$name]=${feature[$name]:-${entry#*:}}
    else
      required[$name]=1  # a command needs it: never only a feature
    fi
    [ -n "${seen[$name]:-}" ] && continue
    seen[$name]=1
    installed "$name" || missing+=("$name")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  if [ "$(id -u)" -ne 0 ]; then
    if command -v sudo >/dev/null; then sudo=(sudo); else
      echo "build.sh: missing packages: ${missing[*]}; install them as root with: apt-get install ${missing[*]}" >&2
      exit 2
    fi
  fi
  export DEBIAN_FRONTEND=noninteractive
  "${sudo[@]}" apt-get update -qq || echo "build.sh: apt-get update failed: the package lists may be old" >&2
  for name in "${missing[@]}"; do
    if has_candidate "$name"; then
      absent+=("$name")
    elif [ -z "${required[$name]:-}" ]; then
      echo "build.sh: $(system_name) has no package $name: ${feature[$name]} will be missing; setting up the rest" >&2
    else
      unavailable+=("$name")
    fi
  done
  if [ ${#unavailable[@]} -gt 0 ]; then
    local hint="the supported systems are Debian 12 and 13 and Ubuntu 22.04 and 24.04 (README.md)"
    grep -qi '^ID=ubuntu' /etc/os-release 2>/dev/null && hint="on Ubuntu, enable the universe component: sudo add-apt-repository universe"
    echo "build.sh: $(system_name) has no package ${unavailable[*]}, which the build needs; $hint" >&2
    exit 2
  fi
  [ ${#absent[@]} -eq 0 ] && return 0
  echo "build.sh: installing packages: ${absent[*]}"
  "${sudo[@]}" apt-get install -y -qq --no-install-recommends "${absent[@]}" >/dev/null
}

# instructors
# The class grader's copy finder, Dolos (from npm: neither Debian nor Ubuntu packages one), at
# the versions tests/grader/copies/package-lock.json pins, into build/copy-finder/: prebuilt,
# no install scripts run, nothing compiled. Without it, a class report says in one line that
# near-copies were not looked for.
install_copy_finder() {
  local source=tests/grader/copies home=build/copy-finder node_major
  cmp -s "$source/package-lock.json" "$home/package-lock.json" && [ -f "$home/installed" ] && return 0
  if ! command -v npm >/dev/null || ! command -v node >/dev/null; then
    echo "build.sh: no Node.js and npm here: class reports will not look for near-copies" >&2
    return 0
  fi
  node_major=$(node -p 'process.versions.node.split(".")[0]')
  if [ "$node_major" -lt 18 ]; then
    echo "build.sh: this system's Node.js is $(node --version); the copy finder (Dolos) needs 18 or newer: class reports will not look for near-copies" >&2
    return 0
  fi
  rm -rf "$home"
  mkdir -p "$home"
  cp "$source/package.json" "$source/package-lock.json" "$home/"
  echo "build.sh: installing the copy finder (Dolos, from npm) into $home"
  if (cd "$home" && npm ci --ignore-scripts --legacy-peer-deps --no-audit --no-fund --loglevel=error) >"$home/npm.log" 2>&1; then
    touch "$home/installed"
  else
    echo "build.sh: the copy finder could not be installed (see $home/npm.log): class reports will not look for near-copies" >&2
  fi
}
# /instructors

# configure: CMake's configure step, with configure_options (below) on top of the preset's.
configure() {
  cmake --preset "$BILLIARD_PRESET" "${configure_options[@]}" >/dev/null
}
# build_targets [TARGET...]: build the given targets, or everything. A student's build (the tasks
# preset) prints only what the compiler says (errors and warnings), not a line per file.
build_targets() {
  local quiet=()
  if [ "$BILLIARD_PRESET" = tasks ]; then
    quiet=(-- --quiet)
    [ -f "build/$BILLIARD_PRESET/.ninja_log" ] || echo "build.sh: building, for the first time (a few minutes)"
  fi
  cmake --build --preset "$BILLIARD_PRESET" ${1:+--target "$@"} "${quiet[@]}"
}
# build [TARGET...]: configure, then build the given targets, or everything.
build() {
  configure
  build_targets "$@"
}
configure_options=()

# Makes Debian's /usr/bin/python3 import the module `billiard` built here: from this checkout's
# folders, and from any folder outside a checkout (lib/python/register_checkout.py: a finder in the
# user's site-packages; no pip, no PyPI). Another checkout imports its own build.
register_python_module() {
  /usr/bin/python3 lib/python/register_checkout.py "build/$BILLIARD_PRESET/python"
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
# student's `./build.sh test -L propagate` builds only that task's suite. A label may be a list
# of labels, "graded|cli" or "^(graded|cli)$". Empty (build everything) when no label is
# selected, or one is another pattern or a label whose tests have not declared what they need
# (build/<preset>/test_labels.txt).
targets_for_labels() {
  targets=()
  local list=build/$BILLIARD_PRESET/test_labels.txt label word words
  [ ${#labels[@]} -gt 0 ] && [ -f "$list" ] || return 0
  for label in "${labels[@]}"; do
    label=${label#^}; label=${label%\$}; label=${label#(}; label=${label%)}
    IFS='|' read -ra words <<< "$label"
    for word in "${words[@]}"; do
      if ! grep -qxF -- "$word" "$list"; then targets=(); return 0; fi
      targets+=("tests_$word")
    done
  done
}

# The tests of a student's run (the tasks preset, no label named): the graded suites of their
# tasks and the tests of the `billiard` and `particles` commands. The engine's, the stepper's, the
# Python module's, the notebooks', the fuzz and the benchmark's tests run when named (-L engine).
STUDENT_LABELS=(graded cli collisions)

# student_run: true for `./build.sh test` in a student's build with no label named.
student_run() {
  [ "$BILLIARD_PRESET" = tasks ] && [ ${#labels[@]} -eq 0 ] && [ "$label_exclude" = 0 ]
}

# select_student_labels: the student's labels this course has (the C track alone has no `billiard`
# command), as one ctest label pattern in `labels`.
select_student_labels() {
  local list=build/$BILLIARD_PRESET/test_labels.txt label present=()
  for label in "${STUDENT_LABELS[@]}"; do
    grep -qxF -- "$label" "$list" && present+=("$label")
  done
  labels=("^($(IFS='|'; echo "${present[*]}"))\$")
}

# selects LABELS_REGEX: whether the selected tests may include tests with those labels (every
# test but a student's run, or a label that names one of them or is a pattern).
selects() {
  local label
  if [ ${#labels[@]} -eq 0 ]; then ! student_run; return; fi
  for label in "${labels[@]}"; do
    [[ "$label" =~ $1|[.*+?\[] ]] && return 0
  done
  return 1
}
# needs_python: the Python module's and the notebooks' tests; needs_test_packages: the grader's.
needs_python() { selects 'python|notebooks'; }
needs_test_packages() { selects 'grader|packages|platforms|contributing'; }

# excluded_labels_named: sets `include_excluded` to "-LE ^$" (exclude nothing) when a selected
# label is one the test presets leave out (stress, platforms, contributing) and the options exclude nothing
# themselves, so that `./build.sh test -L stress` runs those tests.
excluded_labels_named() {
  include_excluded=()
  local label
  [ "$label_exclude" = 1 ] && return 0
  for label in "${labels[@]}"; do
    [[ "$label" =~ stress|platforms|contributing ]] && include_excluded=(-LE '^$')
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
    read_label_options "$@"
    wanted=()
    needs_test_packages && wanted+=("${test_packages[@]}")
    if needs_python; then
      wanted+=("${python_packages[@]}")
      configure_options=(-DBILLIARD_PYTHON=ON)  # the module and notebooks are tested: never skip them
    fi
    install_missing_packages "${wanted[@]}"
    needs_test_packages && install_copy_finder
    configure
    student=()
    if student_run; then
      select_student_labels
      student=(-L "${labels[0]}")
    fi
    targets_for_labels
    excluded_labels_named
    build_targets "${targets[@]}"
    needs_python && register_python_module >/dev/null
    status=0
    results=$PWD/build/$BILLIARD_PRESET/Testing/results.xml
    rm -f "$results"
    progress_options=()
    if [ ${#student[@]} -gt 0 ] && [ $# -eq 0 ]; then
      # A student's whole run: each test's own output goes to the log; the block below says
      # where the tasks stand, and `-L <task>` shows a task's messages.
      log=build/$BILLIARD_PRESET/Testing/output.log
      mkdir -p "${log%/*}"
      echo "build.sh: running the tests of your tasks and of the commands (every test's output: $log)"
      ctest --preset "$BILLIARD_PRESET" --output-junit "$results" "${student[@]}" >"$log" 2>&1 || status=$?
      [ -f "$results" ] || tail -n 20 "$log"
      progress_options=(--counts)
    else
      ctest --preset "$BILLIARD_PRESET" --output-junit "$results" "${student[@]}" "$@" "${include_excluded[@]}" || status=$?
      print_fuzz_counts
    fi
    # The whole command's wall time (set-up, build, tests), then where the tasks stand and what
    # to do next, in a few lines (tests/grader/progress.py).
    echo "build.sh: test took $SECONDS s (set-up, build and tests)"
    [ -f "$results" ] && /usr/bin/python3 tests/grader/progress.py "${progress_options[@]}" "$results"
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
    if [[ " $* " == *" --class "* || " $* " == *" --class="* ]]; then
      install_missing_packages "${class_packages[@]}"
      install_copy_finder
    else
      install_missing_packages
    fi
    exec /usr/bin/python3 tests/grader/grade.py "$@"
    ;;
  setup)
    install_missing_packages
    ;;
  -h|--help|help)
    usage
    ;;
  "")  # no command: what the commands are
    usage
    exit 2
    ;;
  *)
    echo "build.sh: unknown command '${command}'; use './build.sh run' or './build.sh test' (see ./build.sh --help)" >&2
    exit 2
    ;;
esac
