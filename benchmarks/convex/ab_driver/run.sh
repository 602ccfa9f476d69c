#!/bin/sh
# In-process A/B: the headers (and hull builder) of git revision REV against the working tree's, compiled into one
# binary under two namespaces and timed alternately. Usage, from anywhere:
#   benchmarks/convex/ab_driver/run.sh [REV=HEAD] [alternations=7] [pass multiplier=3] [cold|coherent]
# cold (default): the cold boolean GJK on P3-like pairs (ab_variant.cpp, ab_main.cpp); coherent: cold and warm GJK
# distance and boolean, the separating plane and closest features on cdkit_bench_coherent's scenes (ab_coherent.cpp,
# ab_coherent_main.cpp), with each side's cold-distance ratio for each method. Needs g++, Eigen and qhull_r (the library's own dependencies). On a shared machine run
# it under `nice`.
set -e
rev=${1:-HEAD}
rounds=${2:-7}
mult=${3:-3}
what=${4:-cold}
here=$(cd "$(dirname "$0")" && pwd)
root=$(git -C "$here" rev-parse --show-toplevel)
case "$what" in
  cold) variant=ab_variant.cpp; main=ab_main.cpp ;;
  coherent) variant=ab_coherent.cpp; main=ab_coherent_main.cpp ;;
  *) echo "run.sh: unknown A/B '$what' (cold or coherent)" >&2; exit 2 ;;
esac
tmp=$(mktemp -d)
git -C "$root" archive "$rev" include src/convex | tar -x -C "$tmp"
F="-std=c++20 -O3 -DNDEBUG -DCDKIT_NO_PRECOMPILED_QUERIES -isystem /usr/include/eigen3"
g++ $F -I"$tmp/include" -Dcdkit=cdkit_old -Dcdbench=cdbench_old -DVARIANT=old -c "$here/$variant" -o "$tmp/v_old.o"
g++ $F -I"$tmp/include" -Dcdkit=cdkit_old -c "$tmp/src/convex/convex_hull.cpp" -o "$tmp/h_old.o"
g++ $F -I"$root/include" -Dcdkit=cdkit_new -Dcdbench=cdbench_new -DVARIANT=new -c "$here/$variant" -o "$tmp/v_new.o"
g++ $F -I"$root/include" -Dcdkit=cdkit_new -c "$root/src/convex/convex_hull.cpp" -o "$tmp/h_new.o"
g++ $F "$here/$main" "$tmp/v_old.o" "$tmp/v_new.o" "$tmp/h_old.o" "$tmp/h_new.o" -o "$tmp/ab" -lqhull_r
"$tmp/ab" "$rounds" "$mult"
rm -rf "$tmp"
