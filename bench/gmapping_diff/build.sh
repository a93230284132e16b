#!/usr/bin/env bash
# Build the real openslam_gmapping library (no ROS, no catkin) and our differential driver.
#
# usage: bench/gmapping_diff/build.sh UPSTREAM_SRC BUILD_DIR
#   UPSTREAM_SRC  an export of github.com/ros-perception/openslam_gmapping (kept outside the repo)
#   BUILD_DIR     where objects, libgmapping_real.a and the gmapping_diff_driver binary go
# The flags follow a release build of the upstream CMake (-O3, NDEBUG); the upstream commit (from
# UPSTREAM_SRC/.commit when present, else "unknown") is written to BUILD_DIR/upstream_commit.
source "$(dirname "$0")/../diff_build_args.sh"  # strict mode; SRC, BUILD, HERE
if [ ! -f "$SRC/gridfastslam/gridslamprocessor.cpp" ]; then
    echo "$SRC: not an openslam_gmapping source tree (gridfastslam/gridslamprocessor.cpp missing)" >&2
    exit 2
fi
for tool in g++ ar; do
    command -v $tool >/dev/null || { echo "$tool not found (apt-get install g++ binutils)" >&2; exit 2; }
done
CXX=${CXX:-g++}
CXXFLAGS=${CXXFLAGS:-"-O3 -DNDEBUG -fPIC -w"}

# catkin's generate_export_header output: empty export macros (static build).
GEN="$BUILD/gen/gmapping"
for lib in utils sensor/sensor_base sensor/sensor_odometry sensor/sensor_range log configfile \
           scanmatcher gridfastslam; do
    name=$(basename "$lib")
    macro=$(echo "$name" | tr '[:lower:]' '[:upper:]')_EXPORT
    mkdir -p "$GEN/$lib"
    printf '#pragma once\n#define %s\n' "$macro" > "$GEN/$lib/${name}_export.h"
done

SOURCES="utils/stat.cpp utils/movement.cpp
sensor/sensor_base/sensor.cpp sensor/sensor_base/sensorreading.cpp
sensor/sensor_odometry/odometrysensor.cpp sensor/sensor_odometry/odometryreading.cpp
sensor/sensor_range/rangesensor.cpp sensor/sensor_range/rangereading.cpp
log/configuration.cpp log/carmenconfiguration.cpp log/sensorlog.cpp log/sensorstream.cpp
configfile/configfile.cpp
scanmatcher/smmap.cpp scanmatcher/scanmatcher.cpp scanmatcher/scanmatcherprocessor.cpp
scanmatcher/eig3.cpp
gridfastslam/gridslamprocessor_tree.cpp gridfastslam/motionmodel.cpp
gridfastslam/gridslamprocessor.cpp gridfastslam/gfsreader.cpp"

INCLUDES="-I$SRC/include -I$BUILD/gen"
OBJECTS=""
for src in $SOURCES; do
    obj="$BUILD/obj/${src%.cpp}.o"
    mkdir -p "$(dirname "$obj")"
    if [ ! -f "$obj" ] || [ "$SRC/$src" -nt "$obj" ]; then
        $CXX $CXXFLAGS $INCLUDES -c "$SRC/$src" -o "$obj"
    fi
    OBJECTS="$OBJECTS $obj"
done
rm -f "$BUILD/libgmapping_real.a"
ar rcs "$BUILD/libgmapping_real.a" $OBJECTS
$CXX $CXXFLAGS $INCLUDES "$HERE/driver.cpp" "$BUILD/libgmapping_real.a" \
    -o "$BUILD/gmapping_diff_driver.tmp"
mv "$BUILD/gmapping_diff_driver.tmp" "$BUILD/gmapping_diff_driver"
if [ -f "$SRC/.commit" ]; then cp "$SRC/.commit" "$BUILD/upstream_commit"
else echo unknown > "$BUILD/upstream_commit"; fi
echo "built $BUILD/gmapping_diff_driver (upstream $(cat "$BUILD/upstream_commit"))"
