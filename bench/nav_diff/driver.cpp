// Differential driver: runs the real base_local_planner::TrajectoryPlanner
// (ros-planning/navigation) over control cycles captured from slam_predict's local planner, one
// planner instance kept alive across the cycles of a case, and writes its choice per cycle.
//
// usage: nav_diff_driver PARAMS CYCLES OUT
//   PARAMS  params.txt of a case (slam_predict.formats.nav_cycles): "key value" lines
//   CYCLES  cycles.bin of the case (local costmaps and cycles)
//   OUT     text output: "nav_diff_driver 1", then per cycle: index xv thetav cost escaping
//           stuck_left stuck_right rotating_left rotating_right ours_cost
// Each cycle is run as TrajectoryPlannerROS::computeVelocityCommands runs the planner:
// updatePlan(plan) then findBestPath(pose, velocity); the planner is set up as
// TrajectoryPlannerROS::initialize does (constructor, then the first dynamic_reconfigure
// callback's reconfigure(config)). ours_cost is scoreTrajectory of our command on the same grids.
#include <base_local_planner/costmap_model.h>
#include <base_local_planner/trajectory_planner.h>
#include <costmap_2d/costmap_2d.h>
#include <geometry_msgs/PoseStamped.h>
#include <tf2/LinearMath/Quaternion.h>
#include <zlib.h>

#include "record_reader.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace base_local_planner {
// The planner's friend (its unit test's name): reads the mode flags and sets meter_scoring_,
// which the constructor leaves uninitialised.
class TrajectoryPlannerTest {
 public:
  static void SetMeterScoring(TrajectoryPlanner& tp, bool on) { tp.meter_scoring_ = on; }
  static std::string Flags(const TrajectoryPlanner& tp) {
    std::ostringstream out;
    out << tp.escaping_ << ' ' << tp.stuck_left << ' ' << tp.stuck_right << ' '
        << tp.rotating_left << ' ' << tp.rotating_right;
    return out.str();
  }
};
}  // namespace base_local_planner

namespace {

using base_local_planner::TrajectoryPlanner;

[[noreturn]] void Fail(const std::string& what) {
  std::cerr << "nav_diff_driver: " << what << std::endl;
  std::exit(2);
}

struct Params {
  std::map<std::string, double> values;
  std::vector<geometry_msgs::Point> footprint;
  double Get(const std::string& key) const {
    auto it = values.find(key);
    if (it == values.end()) Fail("params: missing " + key);
    return it->second;
  }
};

Params ReadParams(const std::string& path) {
  std::ifstream in(path);
  if (!in) Fail(path + ": cannot open");
  Params out;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::string key;
    if (!(fields >> key)) continue;
    if (key == "footprint") {
      size_t n = 0;
      fields >> n;
      out.footprint.resize(n);
      for (auto& p : out.footprint) fields >> p.x >> p.y;
    } else {
      fields >> out.values[key];
    }
    if (!fields) Fail(path + ": bad line: " + line);
  }
  return out;
}

// The config the first reconfigure callback applies (our values for every field we set).
base_local_planner::BaseLocalPlannerConfig Config(const Params& p) {
  base_local_planner::BaseLocalPlannerConfig c;
  c.acc_lim_x = p.Get("acc_lim_x");
  c.acc_lim_y = p.Get("acc_lim_y");
  c.acc_lim_theta = p.Get("acc_lim_theta");
  c.max_vel_x = p.Get("max_vel_x");
  c.min_vel_x = p.Get("min_vel_x");
  c.max_vel_theta = p.Get("max_vel_theta");
  c.min_vel_theta = p.Get("min_vel_theta");
  c.min_in_place_vel_theta = p.Get("min_in_place_vel_theta");
  c.sim_time = p.Get("sim_time");
  c.sim_granularity = p.Get("sim_granularity");
  c.angular_sim_granularity = p.Get("angular_sim_granularity");
  c.path_distance_bias = p.Get("path_distance_bias");
  c.goal_distance_bias = p.Get("goal_distance_bias");
  c.occdist_scale = p.Get("occdist_scale");
  c.oscillation_reset_dist = p.Get("oscillation_reset_dist");
  c.escape_reset_dist = p.Get("escape_reset_dist");
  c.escape_reset_theta = p.Get("escape_reset_theta");
  c.vx_samples = static_cast<int>(p.Get("vx_samples"));
  c.vtheta_samples = static_cast<int>(p.Get("vtheta_samples"));
  c.heading_lookahead = p.Get("heading_lookahead");
  c.holonomic_robot = p.Get("holonomic_robot") != 0;
  c.escape_vel = p.Get("escape_vel");
  c.dwa = p.Get("dwa") != 0;
  c.heading_scoring = p.Get("heading_scoring") != 0;
  c.heading_scoring_timestep = p.Get("heading_scoring_timestep");
  c.simple_attractor = p.Get("simple_attractor") != 0;
  return c;
}

std::unique_ptr<TrajectoryPlanner> MakePlanner(const Params& p,
                                               base_local_planner::WorldModel& world,
                                               const costmap_2d::Costmap2D& costmap) {
  auto c = Config(p);
  auto tp = std::make_unique<TrajectoryPlanner>(
      world, costmap, p.footprint, c.acc_lim_x, c.acc_lim_y, c.acc_lim_theta, c.sim_time,
      c.sim_granularity, c.vx_samples, c.vtheta_samples, c.path_distance_bias,
      c.goal_distance_bias, c.occdist_scale, c.heading_lookahead, c.oscillation_reset_dist,
      c.escape_reset_dist, c.escape_reset_theta, c.holonomic_robot, c.max_vel_x, c.min_vel_x,
      c.max_vel_theta, c.min_vel_theta, c.min_in_place_vel_theta, c.escape_vel, c.dwa,
      c.heading_scoring, c.heading_scoring_timestep, p.Get("meter_scoring") != 0,
      c.simple_attractor, std::vector<double>(), 0.2, p.Get("sim_period"),
      c.angular_sim_granularity);
  base_local_planner::TrajectoryPlannerTest::SetMeterScoring(*tp, p.Get("meter_scoring") != 0);
  tp->reconfigure(c);
  return tp;
}

// The captured cycles file (bench/nav_diff/record_reader.h).
class Reader : public RecordReader {
 public:
  explicit Reader(const std::string& path)
      : RecordReader(path, "SPNAVC01", "cycles", "nav_diff_driver") {}
};


geometry_msgs::PoseStamped Pose2D(double x, double y, double yaw) {
  geometry_msgs::PoseStamped pose;
  pose.pose.position.x = x;
  pose.pose.position.y = y;
  tf2::Quaternion q;
  q.setRPY(0, 0, yaw);
  pose.pose.orientation.x = q.x();
  pose.pose.orientation.y = q.y();
  pose.pose.orientation.z = q.z();
  pose.pose.orientation.w = q.w();
  return pose;
}

// One cycle: updatePlan + findBestPath as TrajectoryPlannerROS calls them; one output line.
void RunCycle(Reader& in, TrajectoryPlanner& tp, FILE* out) {
  uint32_t index = in.Get<uint32_t>();
  double v[7];  // x y θ, v ω, our vx vθ
  in.Get<double>();  // t
  for (double& value : v) value = in.Get<double>();
  uint32_t n = in.Get<uint32_t>();
  std::vector<geometry_msgs::PoseStamped> plan;
  for (uint32_t k = 0; k < n; ++k) {
    double px = in.Get<double>(), py = in.Get<double>(), pth = in.Get<double>();
    plan.push_back(Pose2D(px, py, pth));
  }
  tp.updatePlan(plan);
  geometry_msgs::PoseStamped pose = Pose2D(v[0], v[1], v[2]);
  geometry_msgs::PoseStamped vel = Pose2D(v[3], 0.0, v[4]);
  geometry_msgs::PoseStamped drive;
  base_local_planner::Trajectory best = tp.findBestPath(pose, vel, drive);
  // our command scored on the grids findBestPath just computed (pose and velocity as floats,
  // as findBestPath passes them on)
  double ours = tp.scoreTrajectory(float(v[0]), float(v[1]), float(v[2]), float(v[3]), 0.0,
                                   float(v[4]), v[5], 0.0, v[6]);
  std::fprintf(out, "%u %.17g %.17g %.17g %s %.17g\n", index, best.xv_, best.thetav_,
               best.cost_, base_local_planner::TrajectoryPlannerTest::Flags(tp).c_str(), ours);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) Fail("usage: nav_diff_driver PARAMS CYCLES OUT");
  Params params = ReadParams(argv[1]);
  Reader in(argv[2]);
  FILE* out = std::fopen(argv[3], "w");
  if (!out) Fail(std::string(argv[3]) + ": cannot write");
  std::fprintf(out, "nav_diff_driver 1\n");
  costmap_2d::Costmap2D costmap;
  base_local_planner::CostmapModel world(costmap);
  std::unique_ptr<TrajectoryPlanner> tp;
  for (;;) {
    char tag = in.Get<char>();
    if (tag == 'E') break;
    if (tag == 'M') {
      in.ReadCostmap(costmap);
      if (!tp) tp = MakePlanner(params, world, costmap);
    } else if (tag == 'C' && tp) {
      RunCycle(in, *tp, out);
    } else {
      Fail(std::string("cycles: bad record tag ") + tag);
    }
  }
  std::fclose(out);
  return 0;
}
