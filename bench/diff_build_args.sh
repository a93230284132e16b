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

# require_headers "PACKAGES" HEADER...: exit 2 naming the first header missing under
# /usr/include and the Debian packages that provide the set.
require_headers() {
    local packages="$1" header
    shift
    for header in "$@"; do
        [ -f "/usr/include/$header" ] || {
            echo "/usr/include/$header missing (apt-get install $packages)" >&2
            exit 2; }
    done
}
