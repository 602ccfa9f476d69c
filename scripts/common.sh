# Shared by scripts/bench and scripts/test: install what is missing, configure and build one tree.
# Usage: source scripts/common.sh; cdkit_build <build-dir> <build-type> [extra cmake args...]
CDKIT_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
CDKIT_JOBS=${CDKIT_JOBS:-$(nproc 2>/dev/null || echo 2)}

cdkit_build() {
  local dir=$1 type=$2
  shift 2
  "$CDKIT_ROOT/scripts/install-deps"
  cmake -S "$CDKIT_ROOT" -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE="$type" "$@"
  cmake --build "$dir" -j "$CDKIT_JOBS"
}
