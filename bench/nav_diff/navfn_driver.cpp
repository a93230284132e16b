// Differential driver for the global planner: runs the real navfn::NavFn
// (ros-planning/navigation) on make_plan requests captured from slam_predict's global planner,
// each as NavfnROS::makePlan handles it, and writes the plans.
//
// usage: navfn_diff_driver PLANS OUT
//   PLANS  plans.bin of a case (bench/nav_diff/plans.py)
//   OUT    text: "navfn_diff_driver 1", then per request "index n x_0 y_0 ... x_n-1 y_n-1"
//          (the plan's points in the costmap frame, m; n = 0: no plan)
// Per request (NavfnROS::makePlan): the robot's cell set FREE (clearRobotCell), the costmap
// converted (setCostmap, ROS costs), the potential propagated from the robot
// (calcNavFnDijkstra(true) with start and goal swapped, as makePlan does), the reachable point
// nearest the goal within ±tolerance searched in resolution steps, the path descended from it
// (calcPath(size_x · 4)), cells to metres as NavfnROS::mapToWorld (origin + cell · resolution),
// and the chosen goal point appended.
#include <costmap_2d/cost_values.h>
#include <costmap_2d/costmap_2d.h>
#include <navfn/navfn.h>
#include <zlib.h>

#include "record_reader.h"

#include <cfloat>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string>
#include <vector>

namespace {

[[noreturn]] void Fail(const std::string& what) {
  std::cerr << "navfn_diff_driver: " << what << std::endl;
  std::exit(2);
}

// The captured plans file (bench/nav_diff/record_reader.h).
class Reader : public RecordReader {
 public:
  explicit Reader(const std::string& path)
      : RecordReader(path, "SPNAVP01", "plans", "navfn_diff_driver") {}
};

struct Request {
  uint32_t index;
  double start_x, start_y, goal_x, goal_y, tolerance;
  bool allow_unknown;
};

Request ReadRequest(Reader& in, costmap_2d::Costmap2D& costmap) {
  Request r;
  r.index = in.Get<uint32_t>();
  in.Get<double>();  // t
  r.start_x = in.Get<double>();
  r.start_y = in.Get<double>();
  r.goal_x = in.Get<double>();
  r.goal_y = in.Get<double>();
  r.tolerance = in.Get<double>();
  r.allow_unknown = in.Get<uint8_t>() != 0;
  in.ReadCostmap(costmap);
  return r;
}

// NavfnROS::getPointPotential
double PointPotential(const costmap_2d::Costmap2D& costmap, const navfn::NavFn& planner,
                      double wx, double wy) {
  unsigned int mx, my;
  if (!costmap.worldToMap(wx, wy, mx, my)) return DBL_MAX;
  return planner.potarr[my * planner.nx + mx];
}

// NavfnROS::makePlan on one request; the plan's points (m).
std::vector<std::pair<double, double>> MakePlan(const Request& r,
                                                costmap_2d::Costmap2D& costmap,
                                                navfn::NavFn& planner) {
  std::vector<std::pair<double, double>> plan;
  unsigned int mx, my;
  if (!costmap.worldToMap(r.start_x, r.start_y, mx, my)) return plan;
  costmap.setCost(mx, my, costmap_2d::FREE_SPACE);
  planner.setNavArr(costmap.getSizeInCellsX(), costmap.getSizeInCellsY());
  planner.setCostmap(costmap.getCharMap(), true, r.allow_unknown);
  int map_start[2] = {int(mx), int(my)};
  if (!costmap.worldToMap(r.goal_x, r.goal_y, mx, my)) {
    if (r.tolerance <= 0.0) return plan;
    mx = 0;
    my = 0;
  }
  int map_goal[2] = {int(mx), int(my)};
  planner.setStart(map_goal);
  planner.setGoal(map_start);
  planner.calcNavFnDijkstra(true);
  const double res = costmap.getResolution();
  double best_x = 0, best_y = 0, best_sdist = DBL_MAX;
  bool found = false;
  for (double py = r.goal_y - r.tolerance; py <= r.goal_y + r.tolerance; py += res) {
    for (double px = r.goal_x - r.tolerance; px <= r.goal_x + r.tolerance; px += res) {
      double sdist = (px - r.goal_x) * (px - r.goal_x) + (py - r.goal_y) * (py - r.goal_y);
      if (PointPotential(costmap, planner, px, py) < POT_HIGH && sdist < best_sdist) {
        best_sdist = sdist;
        best_x = px;
        best_y = py;
        found = true;
      }
    }
  }
  if (!found || !costmap.worldToMap(best_x, best_y, mx, my)) return plan;
  int best_cell[2] = {int(mx), int(my)};
  planner.setStart(best_cell);
  planner.calcPath(costmap.getSizeInCellsX() * 4);
  float* x = planner.getPathX();
  float* y = planner.getPathY();
  for (int i = planner.getPathLen() - 1; i >= 0; --i)
    plan.emplace_back(costmap.getOriginX() + x[i] * res, costmap.getOriginY() + y[i] * res);
  if (!plan.empty()) plan.emplace_back(best_x, best_y);
  return plan;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) Fail("usage: navfn_diff_driver PLANS OUT");
  Reader in(argv[1]);
  FILE* out = std::fopen(argv[2], "w");
  if (!out) Fail(std::string(argv[2]) + ": cannot write");
  std::fprintf(out, "navfn_diff_driver 1\n");
  costmap_2d::Costmap2D costmap;
  navfn::NavFn planner(1, 1);
  for (;;) {
    char tag = in.Get<char>();
    if (tag == 'E') break;
    if (tag != 'P') Fail(std::string("plans: bad record tag ") + tag);
    Request r = ReadRequest(in, costmap);
    auto plan = MakePlan(r, costmap, planner);
    std::fprintf(out, "%u %zu", r.index, plan.size());
    for (const auto& p : plan) std::fprintf(out, " %.17g %.17g", p.first, p.second);
    std::fputc('\n', out);
  }
  std::fclose(out);
  return 0;
}
