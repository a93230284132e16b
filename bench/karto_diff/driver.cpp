// Differential driver: runs the real Karto SDK (slam_toolbox's karto_sdk) with slam_toolbox's
// Ceres solver over a "prepared scans" file written by slam_predict, feeding the scans the way
// slam_toolbox's addScan does, and writes a JSON summary of the run.
//
// usage: karto_diff_driver SCANS CONFIG OUT.json [--gate sync|none] [--threads N]
//                          [--grid-points K]
//   SCANS   prepared scans, "backend karto" variant (slam_predict.formats.prepared_scans)
//   CONFIG  flat slam_toolbox parameters: YAML "key: value" lines or a flat JSON object;
//           missing keys keep the defaults of the Karto Mapper (and of the node's own parameters)
//   --gate  sync (default): slam_toolbox's shouldProcessScan in front of Mapper::Process
//           (first scan passes; then sequence >= 5, minimum_time_interval since the last passed
//           scan, squared travel >= 0.8 minimum_travel_distance^2); none: every scan to Process
//   --threads  TBB worker threads of the scan matcher (default 1)
//   --grid-points  how many times along the run OccupancyGrid::CreateFromScans is timed
//                  (default 4: after a quarter, half, three quarters and all of the input)
// Output (JSON): accepted scans (input index, stamp s, final corrected robot pose m/rad), loop
// closures (input index of the closing scan and of the chain scan it was linked to), CPU s of
// every Process call and of each timed grid build.
#include <karto_sdk/Mapper.h>
#include <ros/ros.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "ceres_solver.hpp"

namespace {

[[noreturn]] void Fail(const std::string& what) {
  std::cerr << "karto_diff_driver: " << what << std::endl;
  std::exit(2);
}

double CpuSeconds() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

struct Scan {
  double stamp;
  double x, y, theta;
  std::vector<double> ranges;
};

struct PreparedScans {
  double laser_x = 0, laser_y = 0, laser_theta = 0;
  std::vector<double> angles;
  double range_min = 0, range_max = 0;
  std::vector<Scan> scans;
};

PreparedScans ReadPreparedScans(const std::string& path) {
  std::ifstream in(path);
  if (!in) Fail(path + ": cannot open");
  std::string line;
  if (!std::getline(in, line) || line != "slam_predict_prepared_scans 1")
    Fail(path + ": not a prepared-scans file (version 1)");
  PreparedScans out;
  bool karto = false;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::string key;
    if (!(fields >> key)) continue;
    if (key == "SCAN") {
      Scan scan;
      fields >> scan.stamp >> scan.x >> scan.y >> scan.theta;
      scan.ranges.resize(out.angles.size());
      for (double& r : scan.ranges) fields >> r;
      if (!fields) Fail(path + ": short SCAN line " + std::to_string(out.scans.size()));
      out.scans.push_back(std::move(scan));
    } else if (key == "backend") {
      std::string name;
      fields >> name;
      karto = (name == "karto");
    } else if (key == "laser_pose") {
      fields >> out.laser_x >> out.laser_y >> out.laser_theta;
    } else if (key == "angles") {
      size_t n = 0;
      fields >> n;
      out.angles.resize(n);
      for (double& a : out.angles) fields >> a;
    } else if (key == "range_min") {
      fields >> out.range_min;
    } else if (key == "range_max") {
      fields >> out.range_max;
    }
  }
  if (!karto) Fail(path + ": no 'backend karto' line");
  if (out.angles.size() < 2 || out.range_max <= 0) Fail(path + ": laser description missing");
  return out;
}

std::string Trim(std::string text) {
  const char* blank = " \t\r\n\"'";
  text.erase(0, text.find_first_not_of(blank));
  text.erase(text.find_last_not_of(blank) + 1);
  return text;
}

// Flat key/value pairs of a YAML file ("key: value" lines, # comments) or a flat JSON object.
std::map<std::string, std::string> ReadConfig(const std::string& path) {
  std::ifstream in(path);
  if (!in) Fail(path + ": cannot open");
  std::stringstream whole;
  whole << in.rdbuf();
  std::string text = whole.str();
  std::map<std::string, std::string> values;
  const bool json = Trim(text).rfind('{', 0) == 0;
  std::vector<std::string> items;
  std::string item;
  for (char c : text) {
    if (c == '\n' || (json && (c == ',' || c == '{' || c == '}'))) {
      items.push_back(item);
      item.clear();
    } else {
      item += c;
    }
  }
  items.push_back(item);
  for (std::string& entry : items) {
    if (!json) entry = entry.substr(0, entry.find('#'));
    const size_t colon = entry.find(':');
    if (colon == std::string::npos) continue;
    const std::string key = Trim(entry.substr(0, colon));
    const std::string value = Trim(entry.substr(colon + 1));
    if (!key.empty() && !value.empty()) values[key] = value;
  }
  return values;
}

class Config {
 public:
  explicit Config(std::map<std::string, std::string> values) : values_(std::move(values)) {}
  bool Has(const std::string& key) const { return values_.count(key) > 0; }
  double Number(const std::string& key, double fallback) const {
    auto it = values_.find(key);
    if (it == values_.end()) return fallback;
    char* end = nullptr;
    const double v = std::strtod(it->second.c_str(), &end);
    if (end == it->second.c_str()) Fail("parameter " + key + ": not a number: " + it->second);
    return v;
  }
  bool Flag(const std::string& key, bool fallback) const {
    auto it = values_.find(key);
    if (it == values_.end()) return fallback;
    if (it->second == "true" || it->second == "True") return true;
    if (it->second == "false" || it->second == "False") return false;
    Fail("parameter " + key + ": not true/false: " + it->second);
  }
  const std::map<std::string, std::string>& All() const { return values_; }

 private:
  std::map<std::string, std::string> values_;
};

// The Mapper parameters slam_toolbox's SMapper::configure sets when the node has them.
void ConfigureMapper(karto::Mapper& m, const Config& c) {
  using M = karto::Mapper;
  const std::vector<std::pair<const char*, void (M::*)(bool)>> flags = {
      {"use_scan_matching", &M::setParamUseScanMatching},
      {"use_scan_barycenter", &M::setParamUseScanBarycenter},
      {"do_loop_closing", &M::setParamDoLoopClosing},
      {"use_response_expansion", &M::setParamUseResponseExpansion}};
  for (const auto& [key, setter] : flags)
    if (c.Has(key)) (m.*setter)(c.Flag(key, false));
  const std::vector<std::pair<const char*, void (M::*)(int)>> counts = {
      {"scan_buffer_size", &M::setParamScanBufferSize},
      {"loop_match_minimum_chain_size", &M::setParamLoopMatchMinimumChainSize}};
  for (const auto& [key, setter] : counts)
    if (c.Has(key)) (m.*setter)(static_cast<int>(c.Number(key, 0)));
  const std::vector<std::pair<const char*, void (M::*)(double)>> numbers = {
      {"minimum_travel_distance", &M::setParamMinimumTravelDistance},
      {"minimum_travel_heading", &M::setParamMinimumTravelHeading},
      {"scan_buffer_maximum_scan_distance", &M::setParamScanBufferMaximumScanDistance},
      {"link_match_minimum_response_fine", &M::setParamLinkMatchMinimumResponseFine},
      {"link_scan_maximum_distance", &M::setParamLinkScanMaximumDistance},
      {"loop_search_maximum_distance", &M::setParamLoopSearchMaximumDistance},
      {"loop_match_maximum_variance_coarse", &M::setParamLoopMatchMaximumVarianceCoarse},
      {"loop_match_minimum_response_coarse", &M::setParamLoopMatchMinimumResponseCoarse},
      {"loop_match_minimum_response_fine", &M::setParamLoopMatchMinimumResponseFine},
      {"correlation_search_space_dimension", &M::setParamCorrelationSearchSpaceDimension},
      {"correlation_search_space_resolution", &M::setParamCorrelationSearchSpaceResolution},
      {"correlation_search_space_smear_deviation",
       &M::setParamCorrelationSearchSpaceSmearDeviation},
      {"loop_search_space_dimension", &M::setParamLoopSearchSpaceDimension},
      {"loop_search_space_resolution", &M::setParamLoopSearchSpaceResolution},
      {"loop_search_space_smear_deviation", &M::setParamLoopSearchSpaceSmearDeviation},
      {"distance_variance_penalty", &M::setParamDistanceVariancePenalty},
      {"angle_variance_penalty", &M::setParamAngleVariancePenalty},
      {"fine_search_angle_offset", &M::setParamFineSearchAngleOffset},
      {"coarse_search_angle_offset", &M::setParamCoarseSearchAngleOffset},
      {"coarse_angle_resolution", &M::setParamCoarseAngleResolution},
      {"minimum_angle_penalty", &M::setParamMinimumAnglePenalty},
      {"minimum_distance_penalty", &M::setParamMinimumDistancePenalty}};
  for (const auto& [key, setter] : numbers)
    if (c.Has(key)) (m.*setter)(c.Number(key, 0));
}

// The laser as slam_toolbox's LaserAssistant::makeLaser describes it.
karto::LaserRangeFinder* MakeLaser(const PreparedScans& in, const Config& c) {
  const double angle_min = in.angles.front();
  const double angle_max = in.angles.back();
  const double increment = (angle_max - angle_min) / (in.angles.size() - 1);
  auto* laser = karto::LaserRangeFinder::CreateLaserRangeFinder(
      karto::LaserRangeFinder_Custom, karto::Name("Custom Described Lidar"));
  laser->SetOffsetPose(karto::Pose2(in.laser_x, in.laser_y, in.laser_theta));
  laser->SetMinimumRange(in.range_min);
  laser->SetMaximumRange(in.range_max);
  laser->SetMinimumAngle(angle_min);
  laser->SetMaximumAngle(angle_max);
  laser->SetAngularResolution(increment);
  const float angular_range = std::fabs(angle_max - angle_min);
  bool is_360 = std::fabs(angular_range - 2.0 * M_PI) <
                (increment - (std::numeric_limits<float>::epsilon() * 2.0f * M_PI));
  if (angular_range > 6.10865 && (angular_range / increment) + 1 == in.angles.size())
    is_360 = false;
  laser->SetIs360Laser(is_360);
  laser->SetRangeThreshold(std::min(c.Number("max_laser_range", 25.0), in.range_max));
  return laser;
}

// slam_toolbox's SlamToolbox::shouldProcessScan (sync mode), sequence = input index.
class ScanGate {
 public:
  ScanGate(const Config& c, double minimum_travel_distance)
      : interval_(c.Number("minimum_time_interval", 0.5)),
        throttle_(static_cast<long>(c.Number("throttle_scans", 1))),
        min_dist2_(minimum_travel_distance * minimum_travel_distance) {}
  bool Pass(long seq, double stamp, const karto::Pose2& pose) {
    if (first_) {
      first_ = false;
      Remember(stamp, pose);
      return true;
    }
    if (seq % throttle_ != 0) return false;
    if (stamp - last_stamp_ < interval_) return false;
    if (last_pose_.SquaredDistance(pose) < 0.8 * min_dist2_ || seq < 5) return false;
    Remember(stamp, pose);
    return true;
  }

 private:
  void Remember(double stamp, const karto::Pose2& pose) {
    last_stamp_ = stamp;
    last_pose_ = pose;
  }
  double interval_;
  long throttle_;
  double min_dist2_;
  bool first_ = true;
  double last_stamp_ = 0;
  karto::Pose2 last_pose_;
};

struct LoopClosure {
  long scan;   // input index of the scan that closed the loop
  long chain;  // input index of the chain scan it was linked to (-1: edge already existed)
};

// Records the edges TryCloseLoop adds between FireBeginLoopClosure and FireEndLoopClosure.
class LoopListener : public karto::MapperLoopClosureListener {
 public:
  LoopListener(karto::Mapper* mapper, const std::map<const karto::LocalizedRangeScan*, long>* ids)
      : mapper_(mapper), ids_(ids) {}
  void BeginLoopClosure(const std::string&) override {
    edges_before_ = mapper_->GetGraph()->GetEdges().size();
  }
  void EndLoopClosure(const std::string&) override {
    const auto& edges = mapper_->GetGraph()->GetEdges();
    if (edges.size() == edges_before_) closures.push_back({current_scan, -1});
    for (size_t i = edges_before_; i < edges.size(); ++i) {
      const auto* source = edges[i]->GetSource()->GetObject();
      auto it = ids_->find(source);
      closures.push_back({current_scan, it == ids_->end() ? -1 : it->second});
    }
  }
  long current_scan = -1;
  std::vector<LoopClosure> closures;

 private:
  karto::Mapper* mapper_;
  const std::map<const karto::LocalizedRangeScan*, long>* ids_;
  size_t edges_before_ = 0;
};

struct GridTiming {
  long after_input;
  size_t accepted;
  double cpu_s;
  long cells;
};

std::string Num(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}

void SetSolverParams(const Config& c) {
  const char* names[] = {"ceres_linear_solver", "ceres_preconditioner", "ceres_dogleg_type",
                         "ceres_trust_strategy", "ceres_loss_function", "mode", "debug_logging"};
  for (const char* name : names) {
    auto it = c.All().find(name);
    if (it != c.All().end()) ros::stub_params()[name] = it->second;
  }
}

// Every graph edge in insertion order: [source input index, target input index, the LinkInfo
// pose difference dx dy dtheta (source frame), its covariance c00 c01 c02 c11 c12 c22].
void WriteEdges(std::ostream& out, karto::Mapper& mapper,
                const std::map<const karto::LocalizedRangeScan*, long>& ids) {
  const auto& edges = mapper.GetGraph()->GetEdges();
  for (size_t i = 0; i < edges.size(); ++i) {
    auto* info = static_cast<karto::LinkInfo*>(edges[i]->GetLabel());
    const karto::Pose2 d = info->GetPoseDifference();
    const karto::Matrix3 c = info->GetCovariance();
    const auto source = ids.find(edges[i]->GetSource()->GetObject());
    const auto target = ids.find(edges[i]->GetTarget()->GetObject());
    out << (i ? ",\n  " : "\n  ") << "[" << (source == ids.end() ? -1 : source->second) << ", "
        << (target == ids.end() ? -1 : target->second) << ", " << Num(d.GetX()) << ", "
        << Num(d.GetY()) << ", " << Num(d.GetHeading()) << ", " << Num(c(0, 0)) << ", "
        << Num(c(0, 1)) << ", " << Num(c(0, 2)) << ", " << Num(c(1, 1)) << ", "
        << Num(c(1, 2)) << ", " << Num(c(2, 2)) << "]";
  }
}

struct Options {
  std::string scans, config, out, gate = "sync";
  int threads = 1;
  int grid_points = 4;
};

Options ParseArgs(int argc, char** argv) {
  if (argc < 4) Fail("usage: karto_diff_driver SCANS CONFIG OUT.json [--gate sync|none] "
                     "[--threads N] [--grid-points K]");
  Options o{argv[1], argv[2], argv[3]};
  for (int i = 4; i + 1 < argc; i += 2) {
    const std::string flag = argv[i], value = argv[i + 1];
    if (flag == "--gate" && (value == "sync" || value == "none")) o.gate = value;
    else if (flag == "--threads") o.threads = std::max(1, std::atoi(value.c_str()));
    else if (flag == "--grid-points") o.grid_points = std::max(0, std::atoi(value.c_str()));
    else Fail("unknown option " + flag + " " + value);
  }
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  const Options opt = ParseArgs(argc, argv);
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, opt.threads);
  const PreparedScans input = ReadPreparedScans(opt.scans);
  const Config config(ReadConfig(opt.config));
  SetSolverParams(config);

  const double cpu_start = CpuSeconds();
  auto mapper = std::make_unique<karto::Mapper>();
  ConfigureMapper(*mapper, config);
  solver_plugins::CeresSolver solver;
  mapper->SetScanSolver(&solver);
  karto::Dataset dataset;
  karto::LaserRangeFinder* laser = MakeLaser(input, config);
  dataset.Add(laser, true);

  std::map<const karto::LocalizedRangeScan*, long> input_index;
  LoopListener loops(mapper.get(), &input_index);
  mapper->AddListener(&loops);
  ScanGate gate(config, mapper->getParamMinimumTravelDistance());
  const double resolution = config.Number("resolution", 0.05);

  std::vector<std::pair<long, double>> process_cpu;  // (input index, CPU s) per Process call
  std::vector<karto::LocalizedRangeScan*> accepted;
  std::vector<karto::Pose2> at_process;  // each accepted scan's pose when Process returned
  std::vector<GridTiming> grids;
  const long n = static_cast<long>(input.scans.size());
  long next_grid = 1;
  for (long k = 0; k < n; ++k) {
    const Scan& s = input.scans[k];
    const karto::Pose2 odom(s.x, s.y, s.theta);
    if (opt.gate == "none" || gate.Pass(k, s.stamp, odom)) {
      auto* scan = new karto::LocalizedRangeScan(laser->GetName(), s.ranges);
      scan->SetOdometricPose(odom);
      scan->SetCorrectedPose(odom);
      input_index[scan] = k;
      loops.current_scan = k;
      karto::Matrix3 covariance;
      covariance.SetToIdentity();
      const double t0 = CpuSeconds();
      const bool processed = mapper->Process(scan, &covariance);
      process_cpu.emplace_back(k, CpuSeconds() - t0);
      if (processed) {
        dataset.Add(scan);
        accepted.push_back(scan);
        at_process.push_back(scan->GetCorrectedPose());
      } else {
        input_index.erase(scan);
        delete scan;
      }
    }
    while (opt.grid_points > 0 && next_grid <= opt.grid_points &&
           k + 1 >= (n * next_grid) / opt.grid_points) {
      const double t0 = CpuSeconds();
      std::unique_ptr<karto::OccupancyGrid> grid(
          karto::OccupancyGrid::CreateFromScans(mapper->GetAllProcessedScans(), resolution));
      const double cpu = CpuSeconds() - t0;
      const long cells = grid ? static_cast<long>(grid->GetWidth()) * grid->GetHeight() : 0;
      grids.push_back({k, accepted.size(), cpu, cells});
      ++next_grid;
    }
  }
  const double cpu_total = CpuSeconds() - cpu_start;

  std::ofstream out(opt.out + ".tmp");
  out << "{\"format\": \"karto_driver 1\", \"gate\": \"" << opt.gate
      << "\", \"threads\": " << opt.threads << ", \"scans_in\": " << n
      << ", \"cpu_total_s\": " << Num(cpu_total) << ",\n \"accepted\": [";
  for (size_t i = 0; i < accepted.size(); ++i) {
    const karto::Pose2 p = accepted[i]->GetCorrectedPose();
    const long k = input_index[accepted[i]];
    out << (i ? ",\n  " : "\n  ") << "[" << k << ", " << Num(input.scans[k].stamp) << ", "
        << Num(p.GetX()) << ", " << Num(p.GetY()) << ", " << Num(p.GetHeading()) << "]";
  }
  out << "],\n \"loop_closures\": [";
  for (size_t i = 0; i < loops.closures.size(); ++i)
    out << (i ? ", " : "") << "[" << loops.closures[i].scan << ", " << loops.closures[i].chain
        << "]";
  out << "],\n \"pose_at_process\": [";
  for (size_t i = 0; i < at_process.size(); ++i)
    out << (i ? ",\n  " : "\n  ") << "[" << input_index[accepted[i]] << ", "
        << Num(at_process[i].GetX()) << ", " << Num(at_process[i].GetY()) << ", "
        << Num(at_process[i].GetHeading()) << "]";
  out << "],\n \"edges\": [";
  WriteEdges(out, *mapper, input_index);
  out << "],\n \"process_cpu_s\": [";
  for (size_t i = 0; i < process_cpu.size(); ++i)
    out << (i ? ", " : "") << "[" << process_cpu[i].first << ", "
        << Num(process_cpu[i].second) << "]";
  out << "],\n \"grid_cpu\": [";
  for (size_t i = 0; i < grids.size(); ++i)
    out << (i ? ", " : "") << "{\"after_input\": " << grids[i].after_input
        << ", \"accepted\": " << grids[i].accepted << ", \"cells\": " << grids[i].cells
        << ", \"resolution\": " << Num(resolution) << ", \"cpu_s\": " << Num(grids[i].cpu_s)
        << "}";
  out << "]}\n";
  out.close();
  if (!out) Fail(opt.out + ": cannot write");
  std::rename((opt.out + ".tmp").c_str(), opt.out.c_str());
  std::_Exit(0);  // the Dataset, the Mapper and the solver share scan ownership: skip teardown
}
