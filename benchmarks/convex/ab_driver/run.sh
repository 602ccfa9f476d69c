#!/bin/sh
# In-process A/B of the cold boolean GJK: the headers (and hull builder) of git revision REV against the working
# tree's, compiled into one binary under two namespaces and timed alternately (ab_main.cpp). Usage, from anywhere:
#   benchmarks/convex/ab_driver/run.sh [REV=HEAD] [alternations=7] [pass multiplier=3]
# Needs g++, Eigen and qhull_r (the library's own dependencies). On a shared machine run it under `nice`.
set -e
rev=${1:-HEAD}
rounds=${2:-7}
mult=${3:-3}
here=$(cd "$(dirname "$0")" && pwd)
root=$(git -C "$here" rev-parse --show-toplevel)
tmp=$(mktemp -d)
git -C "$root" archive "$rev" include src/convex | tar -x -C "$tmp"
F="-std=c++20 -O3 -DNDEBUG -DCDKIT_NO_PRECOMPILED_QUERIES -isystem /usr/include/eigen3"
g++ $F -I"$tmp/include" -Dcdkit=cdkit_old -DVARIANT=old -c "$here/ab_variant.cpp" -o "$tmp/v_old.o"
g++ $F -I"$tmp/include" -Dcdkit=cdkit_old -c "$tmp/src/convex/convex_hull.cpp" -o "$tmp/h_old.o"
g++ $F -I"$root/include" -Dcdkit=cdkit_new -DVARIANT=new -c "$here/ab_variant.cpp" -o "$tmp/v_new.o"
g++ $F -I"$root/include" -Dcdkit=cdkit_new -c "$root/src/convex/convex_hull.cpp" -o "$tmp/h_new.o"
g++ $F "$here/ab_main.cpp" "$tmp/v_old.o" "$tmp/v_new.o" "$tmp/h_old.o" "$tmp/h_new.o" -o "$tmp/ab" -lqhull_r
"$tmp/ab" "$rounds" "$mult"
rm -rf "$tmp"
