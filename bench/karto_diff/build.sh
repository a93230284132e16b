#!/usr/bin/env bash
# Build the real Karto SDK of slam_toolbox (lib/karto_sdk) and slam_toolbox's Ceres solver
# without ROS or catkin, plus our differential driver.
#
# usage: bench/karto_diff/build.sh UPSTREAM_SRC BUILD_DIR
#   UPSTREAM_SRC  an export of github.com/SteveMacenski/slam_toolbox (its slam_toolbox package
#                 folder, holding lib/karto_sdk and solvers; kept outside the repo)
#   BUILD_DIR     where the stub headers, objects and the karto_diff_driver binary go
# Needs (Debian): g++ libceres-dev libeigen3-dev libboost-dev libboost-thread-dev
# libboost-serialization-dev libtbb-dev. Flags follow upstream's Release CMake (-O3 -DNDEBUG,
# C++17, -fpermissive). The ROS headers the solver includes (logging, NodeHandle::getParam,
# pluginlib's export macro, std_srvs) are replaced by stubs generated into BUILD_DIR; oneTBB's
# missing tbb::parallel_do is provided there as tbb::parallel_for_each (same per-element calls).
# The upstream commit (UPSTREAM_SRC/.commit when present, else "unknown") goes to
# BUILD_DIR/upstream_commit.
source "$(dirname "$0")/../diff_build_args.sh"  # strict mode; SRC, BUILD, HERE
if [ ! -f "$SRC/lib/karto_sdk/src/Mapper.cpp" ] || [ ! -f "$SRC/solvers/ceres_solver.cpp" ]; then
    echo "$SRC: not a slam_toolbox package tree (lib/karto_sdk/src/Mapper.cpp or" \
         "solvers/ceres_solver.cpp missing)" >&2
    exit 2
fi
command -v g++ >/dev/null || { echo "g++ not found (apt-get install g++)" >&2; exit 2; }
require_headers "libceres-dev libeigen3-dev libboost-dev libboost-thread-dev"\
" libboost-serialization-dev libtbb-dev" \
    ceres/ceres.h eigen3/Eigen/Core boost/thread.hpp tbb/parallel_for_each.h
CXX=${CXX:-g++}
CXXFLAGS=${CXXFLAGS:-"-O3 -DNDEBUG -std=c++17 -fPIC -fpermissive -w"}

# --- stub headers (ours), generated at build time --------------------------------------------
GEN="$BUILD/gen"
mkdir -p "$GEN/ros" "$GEN/pluginlib" "$GEN/std_srvs" "$GEN/tbb"
cat > "$GEN/ros/ros.h" <<'STUB'
#pragma once
// Stand-in for the parts of roscpp the Ceres solver plugin uses.
#include <cstdio>
#include <map>
#include <string>
namespace ros {
inline std::map<std::string, std::string>& stub_params() {
  static std::map<std::string, std::string> values;
  return values;
}
class NodeHandle {
 public:
  explicit NodeHandle(const std::string& = "") {}
  bool getParam(const std::string& key, std::string& value) const {
    auto it = stub_params().find(key);
    if (it == stub_params().end()) return false;
    value = it->second;
    return true;
  }
  bool getParam(const std::string& key, bool& value) const {
    std::string text;
    if (!getParam(key, text)) return false;
    value = (text == "true" || text == "True" || text == "1");
    return true;
  }
};
struct Time {
  double seconds = 0.0;
  static Time now() { return Time(); }
};
}  // namespace ros
#define ROS_DEBUG(...) ((void)0)
#define ROS_INFO(...) ((void)0)
#define ROS_WARN(...) (std::fprintf(stderr, __VA_ARGS__), std::fputc('\n', stderr))
#define ROS_ERROR(...) (std::fprintf(stderr, __VA_ARGS__), std::fputc('\n', stderr))
STUB
printf '#pragma once\n#include <ros/ros.h>\n' > "$GEN/ros/console.h"
printf '#pragma once\n#define PLUGINLIB_EXPORT_CLASS(cls, base)\n' \
    > "$GEN/pluginlib/class_list_macros.h"
printf '#pragma once\n' > "$GEN/std_srvs/Empty.h"
cat > "$GEN/tbb/parallel_do.h" <<'STUB'
#pragma once
// oneTBB dropped parallel_do; parallel_for_each calls the body once per element the same way.
#include <tbb/parallel_for_each.h>
namespace tbb {
template <typename Container, typename Body>
void parallel_do(Container& items, const Body& body) {
  tbb::parallel_for_each(items.begin(), items.end(), body);
}
}  // namespace tbb
STUB
# The solver includes "../include/slam_toolbox/toolbox_types.hpp" (ROS message types); its
# sources are copied beside a stub of that header so the relative include finds the stub.
SOLVER="$BUILD/solver_src"
mkdir -p "$SOLVER/solvers" "$SOLVER/include/slam_toolbox"
cp "$SRC/solvers/ceres_solver.cpp" "$SRC/solvers/ceres_solver.hpp" "$SRC/solvers/ceres_utils.h" \
    "$SOLVER/solvers/"
cat > "$SOLVER/include/slam_toolbox/toolbox_types.hpp" <<'STUB'
#pragma once
// Stand-in for slam_toolbox's toolbox_types.hpp: only the graph iterators the solver uses.
#include <unordered_map>
#include <Eigen/Core>
#include <karto_sdk/Mapper.h>
namespace toolbox_types {
typedef std::unordered_map<int, Eigen::Vector3d>::iterator GraphIterator;
typedef std::unordered_map<int, Eigen::Vector3d>::const_iterator ConstGraphIterator;
}  // namespace toolbox_types
STUB

# --- compile ---------------------------------------------------------------------------------
INCLUDES="-I$GEN -I$SRC/lib/karto_sdk/include -I/usr/include/eigen3 -I$SOLVER/solvers"
mkdir -p "$BUILD/obj"
compile() {  # compile SOURCE OBJECT (skipped when the object is newer than the source)
    if [ ! -f "$2" ] || [ "$1" -nt "$2" ]; then
        $CXX $CXXFLAGS $INCLUDES -c "$1" -o "$2"
    fi
}
compile "$SRC/lib/karto_sdk/src/Karto.cpp" "$BUILD/obj/Karto.o"
compile "$SRC/lib/karto_sdk/src/Mapper.cpp" "$BUILD/obj/Mapper.o"
compile "$SOLVER/solvers/ceres_solver.cpp" "$BUILD/obj/ceres_solver.o"
$CXX $CXXFLAGS $INCLUDES "$HERE/driver.cpp" "$BUILD/obj/Karto.o" "$BUILD/obj/Mapper.o" \
    "$BUILD/obj/ceres_solver.o" -lceres -lglog -lboost_serialization -lboost_thread \
    -lboost_system -ltbb -lpthread -o "$BUILD/karto_diff_driver.tmp"
mv "$BUILD/karto_diff_driver.tmp" "$BUILD/karto_diff_driver"
if [ -f "$SRC/.commit" ]; then cp "$SRC/.commit" "$BUILD/upstream_commit"
else echo unknown > "$BUILD/upstream_commit"; fi
echo "built $BUILD/karto_diff_driver (upstream $(cat "$BUILD/upstream_commit"))"
