#!/usr/bin/env bash
# The checker passes on this tree, and refuses a tree with a file of 601 lines and one with a
# function of 121 lines, naming the file and the function (a check that cannot fail proves nothing).
set -euo pipefail
root=$1
check="$root/scripts/source-limits"
"$check" --root "$root"

scratch=$(mktemp -d); trap 'rm -rf "$scratch"' EXIT
mkdir -p "$scratch/view/x/src" "$scratch/controller" "$scratch/protocol"
# A function of exactly 120 lines passes; one more line and it is refused.
body() { echo "int $1() {"; for ((i = 0; i < $2 - 2; ++i)); do echo "  int v$i = $i; (void)v$i;"; done; echo "  return 0;"; echo "}"; }
body fits 119 > "$scratch/view/x/src/fits.cpp"
"$check" --root "$scratch" > "$scratch/out" || { cat "$scratch/out"; echo "FAIL: a 120-line function was refused"; exit 1; }
body too_long 120 > "$scratch/view/x/src/long.cpp"
if "$check" --root "$scratch" > "$scratch/out"; then echo "FAIL: a 121-line function passed"; exit 1; fi
grep -q "view/x/src/long.cpp:1: too_long is 121 lines" "$scratch/out" || { cat "$scratch/out"; echo "FAIL: message"; exit 1; }
rm "$scratch/view/x/src/long.cpp"
# Tests are not product sources: a long test file passes; a long product file does not.
mkdir -p "$scratch/view/x/tests"; seq 700 | sed 's|^|// |' > "$scratch/view/x/tests/long_test.cpp"
"$check" --root "$scratch" > "$scratch/out" || { cat "$scratch/out"; echo "FAIL: a test file was measured"; exit 1; }
seq 601 | sed 's|^|// |' > "$scratch/view/x/src/big.hpp"
if "$check" --root "$scratch" > "$scratch/out"; then echo "FAIL: a 601-line file passed"; exit 1; fi
grep -q "view/x/src/big.hpp: 601 lines" "$scratch/out" || { cat "$scratch/out"; echo "FAIL: message"; exit 1; }
echo "source-limits: the tree passes; 121-line functions and 601-line files are refused"
