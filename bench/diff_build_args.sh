# Sourced by the differential checks' build scripts (bench/*_diff/build.sh): strict mode and the
# two arguments UPSTREAM_SRC BUILD_DIR, resolved to absolute paths in SRC and BUILD (BUILD_DIR is
# created); HERE is the calling script's folder.
set -euo pipefail
if [ $# -ne 2 ]; then
    echo "usage: $0 UPSTREAM_SRC BUILD_DIR" >&2
    exit 2
fi
SRC=$(cd "$1" && pwd)
mkdir -p "$2"
BUILD=$(cd "$2" && pwd)
HERE=$(cd "$(dirname "$0")" && pwd)
