#!/usr/bin/env bash
# Build the real base_local_planner TrajectoryPlanner (with costmap_2d's Costmap2D core) of
# ros-planning/navigation without catkin, plus our differential driver.
#
# usage: bench/nav_diff/build.sh UPSTREAM_SRC BUILD_DIR
#   UPSTREAM_SRC  an export of github.com/ros-planning/navigation (noetic-devel; its
#                 base_local_planner and costmap_2d folders at least; kept outside the repo)
#   BUILD_DIR     where the stub headers, objects and the nav_diff_driver (and, when the
#                 export has navfn, navfn_diff_driver) binaries go
# Needs (Debian): g++ libroscpp-dev librosconsole-dev libtf2-ros-dev (geometry_msgs, tf2 and
# roscpp headers) libeigen3-dev libboost-dev libboost-thread-dev zlib1g-dev. Compiled from
# upstream: base_local_planner's trajectory_planner, map_grid, map_cell, costmap_model,
# footprint_helper, trajectory; costmap_2d's costmap_2d, costmap_math, footprint, array_parser.
# Generated headers and packages without Debian headers (the dynamic_reconfigure config struct,
# the Position2DInt message, angles, sensor_msgs' point clouds, which are only named) are
# replaced by stubs generated into BUILD_DIR. Flags: -O2 -DNDEBUG, C++17 (catkin's Release
# default is -O3; without -ffast-math the level does not change x86-64 IEEE results).
# The upstream commit (UPSTREAM_SRC/.commit when present, else "unknown") goes to
# BUILD_DIR/upstream_commit.
source "$(dirname "$0")/../diff_build_args.sh"  # strict mode; SRC, BUILD, HERE
BLP="$SRC/base_local_planner"
C2D="$SRC/costmap_2d"
if [ ! -f "$BLP/src/trajectory_planner.cpp" ] || [ ! -f "$C2D/src/costmap_2d.cpp" ]; then
    echo "$SRC: not a navigation tree (base_local_planner/src/trajectory_planner.cpp or" \
         "costmap_2d/src/costmap_2d.cpp missing)" >&2
    exit 2
fi
command -v g++ >/dev/null || { echo "g++ not found (apt-get install g++)" >&2; exit 2; }
require_headers "libroscpp-dev librosconsole-dev libtf2-ros-dev libeigen3-dev libboost-dev"\
" libboost-thread-dev zlib1g-dev" \
    ros/ros.h geometry_msgs/PoseStamped.h tf2/utils.h eigen3/Eigen/Core boost/thread.hpp \
    tf2_geometry_msgs/tf2_geometry_msgs.h zlib.h
CXX=${CXX:-g++}
CXXFLAGS=${CXXFLAGS:-"-O2 -DNDEBUG -std=c++17 -w"}

# --- stub headers (ours), generated at build time --------------------------------------------
GEN="$BUILD/gen"
mkdir -p "$GEN/base_local_planner" "$GEN/angles" "$GEN/sensor_msgs"
cat > "$GEN/base_local_planner/BaseLocalPlannerConfig.h" <<'STUB'
#pragma once
// Stand-in for the dynamic_reconfigure struct generated from cfg/BaseLocalPlanner.cfg:
// the same fields, with the .cfg defaults.
#include <cmath>
#include <string>
namespace base_local_planner {
struct BaseLocalPlannerConfig {
  double acc_lim_x = 2.5, acc_lim_y = 2.5, acc_lim_theta = 3.2;
  double max_vel_x = 0.55, min_vel_x = 0.0;
  double max_vel_theta = 1.0, min_vel_theta = -1.0, min_in_place_vel_theta = 0.4;
  double sim_time = 1.7, sim_granularity = 0.025, angular_sim_granularity = 0.025;
  double path_distance_bias = 0.6, goal_distance_bias = 0.8, occdist_scale = 0.01;
  double oscillation_reset_dist = 0.05, escape_reset_dist = 0.10, escape_reset_theta = M_PI / 2;
  int vx_samples = 20, vtheta_samples = 20;
  double heading_lookahead = 0.325;
  bool holonomic_robot = true;
  double escape_vel = -0.1;
  bool dwa = false, heading_scoring = false;
  double heading_scoring_timestep = 0.1;
  bool simple_attractor = false;
  std::string y_vels = "-0.3,-0.1,0.1,-0.3";
  bool restore_defaults = false;
};
}  // namespace base_local_planner
STUB
cat > "$GEN/base_local_planner/Position2DInt.h" <<'STUB'
#pragma once
// Stand-in for the generated message base_local_planner/Position2DInt (int64 x, int64 y).
#include <cstdint>
namespace base_local_planner {
struct Position2DInt {
  int64_t x = 0;
  int64_t y = 0;
};
}  // namespace base_local_planner
STUB
cat > "$GEN/angles/angles.h" <<'STUB'
#pragma once
// Stand-in for the two functions of the angles package the planner uses.
#include <cmath>
namespace angles {
inline double normalize_angle_positive(double a) {
  return std::fmod(std::fmod(a, 2.0 * M_PI) + 2.0 * M_PI, 2.0 * M_PI);
}
inline double normalize_angle(double a) {
  a = normalize_angle_positive(a);
  return a > M_PI ? a - 2.0 * M_PI : a;
}
inline double shortest_angular_distance(double from, double to) {
  return normalize_angle(to - from);
}
}  // namespace angles
STUB
for cloud in PointCloud PointCloud2; do
    printf '%s\n' '#pragma once' '// Stand-in: only named by headers the planner includes.' \
        "namespace sensor_msgs { struct $cloud {}; }" > "$GEN/sensor_msgs/$cloud.h"
done

# --- compile ---------------------------------------------------------------------------------
INCLUDES="-I$GEN -I$BLP/include -I$C2D/include -I/usr/include/eigen3"
mkdir -p "$BUILD/obj"
OBJECTS=()
compile() {  # compile SOURCE NAME (skipped when the object is newer than the source)
    local object="$BUILD/obj/$2.o"
    if [ ! -f "$object" ] || [ "$1" -nt "$object" ]; then
        $CXX $CXXFLAGS $INCLUDES -c "$1" -o "$object"
    fi
    OBJECTS+=("$object")
}
for name in trajectory_planner map_grid map_cell costmap_model footprint_helper trajectory; do
    compile "$BLP/src/$name.cpp" "blp_$name"
done
for name in costmap_2d costmap_math footprint array_parser; do
    compile "$C2D/src/$name.cpp" "c2d_$name"
done
$CXX $CXXFLAGS $INCLUDES "$HERE/driver.cpp" "${OBJECTS[@]}" -lroscpp -lrosconsole \
    -lroscpp_serialization -lrostime -lxmlrpcpp -lcpp_common -lboost_thread -lboost_system \
    -lz -lpthread -o "$BUILD/nav_diff_driver.tmp"
mv "$BUILD/nav_diff_driver.tmp" "$BUILD/nav_diff_driver"
# navfn (when the export has it): NavFn with our navfn_driver.cpp, which replays
# NavfnROS::makePlan on captured requests
if [ -f "$SRC/navfn/src/navfn.cpp" ]; then
    OBJECTS=()
    INCLUDES="$INCLUDES -I$SRC/navfn/include"
    compile "$SRC/navfn/src/navfn.cpp" navfn_navfn
    compile "$C2D/src/costmap_2d.cpp" c2d_costmap_2d
    $CXX $CXXFLAGS $INCLUDES "$HERE/navfn_driver.cpp" "${OBJECTS[@]}" -lrosconsole -lrostime \
        -lcpp_common -lboost_thread -lboost_system -lz -lpthread -o "$BUILD/navfn_diff_driver.tmp"
    mv "$BUILD/navfn_diff_driver.tmp" "$BUILD/navfn_diff_driver"
fi
if [ -f "$SRC/.commit" ]; then cp "$SRC/.commit" "$BUILD/upstream_commit"
else echo unknown > "$BUILD/upstream_commit"; fi
echo "built $BUILD/nav_diff_driver (upstream $(cat "$BUILD/upstream_commit"))"
