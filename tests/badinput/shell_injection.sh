#!/usr/bin/env bash
# Issue 15, item 1: an output folder named  q'; touch owned; echo '  (from -o or from a scene's
# Output/Directory) must be used as a folder name and nothing else. Before the fix, 'converge'
# ran gnuplot through a shell and this created a file 'owned'. The test asserts that no 'owned'
# appears, that the run succeeds, and that the plot lands in the oddly named folder.
# usage: shell_injection.sh FLEXTRACK SOURCE_DIR WORK_DIR
set -u
exe=$1; src=$2; work=$3
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
status=0
hostile="q'; touch owned; echo '"

check() { # $1: what was run, $2: the folder the results must be in
  if [ -e owned ] || [ -e "$2/owned" ] || [ -e "$src/owned" ]; then
    echo "FAIL ($1): the folder name ran a shell command (a file 'owned' was created)"; status=1
  fi
  if [ ! -s "$2/convergence.csv" ]; then echo "FAIL ($1): no convergence.csv in '$2'"; status=1; fi
  if command -v gnuplot >/dev/null && [ ! -s "$2/convergence.png" ]; then
    echo "FAIL ($1): gnuplot is installed but no convergence.png was made in '$2'"; status=1
  fi
}

# 1. The folder from the command line.
"$exe" converge "$src/tests/input/straight_cantilever.prm" --refinements 1 -o "$hostile" >log_option.txt 2>&1
rc=$?; [ $rc -eq 0 ] || { echo "FAIL (-o): exit status $rc"; cat log_option.txt; status=1; }
check "-o" "$hostile"
rm -rf "$hostile" owned

# 2. The folder from the scene's Output/Directory, and a title that tries to end gnuplot's string.
sed 's/^subsection Modal analysis/subsection Output\n  set Directory = q'"'"'; touch owned; echo '"'"'\nend\nsubsection Modal analysis/' \
  "$src/tests/input/straight_cantilever.prm" >scene.prm
"$exe" converge scene.prm --refinements 1 >log_scene.txt 2>&1
rc=$?; [ $rc -eq 0 ] || { echo "FAIL (Output/Directory): exit status $rc"; cat log_scene.txt; status=1; }
check "Output/Directory" "$hostile"
[ $status -eq 0 ] && echo "no command ran; results are in the folder named by the hostile text"
exit $status
