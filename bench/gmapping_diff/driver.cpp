// Differential driver: runs the real openslam_gmapping over a "prepared scans" file, initialised
// the way the slam_gmapping ROS node initialises it, and writes the best particle's trajectory as
// robot (base) poses, one per processed scan.  Written for slam_predict (bench/gmapping_diff);
// built against an upstream checkout by bench/gmapping_diff/build.sh.
//
// usage: gmapping_diff_driver PREPARED_SCANS OUT_TRAJECTORY [TIMING_OUT]
//
// Input (text, written by slam_predict.formats.prepared_scans):
//   "slam_predict_prepared_scans 1"
//   "<key> <value>" lines: seed, particles, GMapping parameters (slam_gmapping names),
//     maxRange, maxUrange, angle_mode (node | exact)
//   "laser_pose x y theta"            laser pose in the base frame (m, rad)
//   "angles N a_0 ... a_N-1"          beam angles in the laser frame (rad, increasing)
//   "SCAN t x y theta r_0 ... r_N-1"  time (s), robot odometry pose, ranges (m); one per scan
// Conventions, as slam_gmapping: the filter works on the "centred laser", the laser frame turned
// by (a_0 + a_N-1)/2; each scan's odometry pose is robot ⊕ centred laser.  angle_mode "node"
// builds the RangeSensor from the beam count and increment as the node does (its constructor
// sets beam i to -N·inc/2 + i·inc); "exact" overwrites them with a_i - centre.
// Output: "# scan_index time x y theta" header, then one robot pose (map frame) per processed scan
// of the best particle (largest weightSum), oldest first; then "# neff" lines (one per processed
// scan after the first: Neff after scan matching, before resampling) and a "# summary" line.
// TIMING_OUT (optional): the compute (CPU) time slam_gmapping would spend, per processed scan:
//   "scan_index time processScan_s map_update_s nodes line_cells map_cells", map_update_s > 0 on
//   the scans where the node rebuilds its map (first processed scan, then whenever the stamp is
//   more than map_update_interval (key, default 5 s) past the last rebuild), as its updateMap does:
//   a fresh map, every node of the best particle's trajectory re-registered (active area + scan),
//   every cell of the map thresholded.  line_cells = Σ over the rebuild's nodes and beams of the
//   beam's length (min(r, maxUrange)) in cells; map_cells = the rebuilt map's size in cells.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gmapping/gridfastslam/gridslamprocessor.h>
#include <gmapping/sensor/sensor_range/rangesensor.h>
#include <gmapping/utils/stat.h>

namespace {

struct Prepared {
  std::map<std::string, std::string> values;
  double laser[3] = {0.0, 0.0, 0.0};
  std::vector<double> angles;
  std::vector<double> times;
  std::vector<GMapping::OrientedPoint> odometry;
  std::vector<std::vector<double> > ranges;
};

[[noreturn]] void fail(const std::string& where, const std::string& what) {
  std::cerr << where << ": " << what << std::endl;
  std::exit(2);
}

void read_scan(std::istringstream& line, Prepared& in, const std::string& where) {
  double t, x, y, th;
  if (!(line >> t >> x >> y >> th)) fail(where, "SCAN line without time and pose");
  std::vector<double> r(in.angles.size());
  for (double& v : r)
    if (!(line >> v)) fail(where, "SCAN line with fewer ranges than angles");
  in.times.push_back(t);
  in.odometry.push_back(GMapping::OrientedPoint(x, y, th));
  in.ranges.push_back(r);
}

Prepared read_prepared(const std::string& path) {
  std::ifstream file(path.c_str());
  if (!file) fail(path, "cannot open");
  Prepared in;
  std::string text;
  std::getline(file, text);
  if (text.rfind("slam_predict_prepared_scans 1", 0) != 0)
    fail(path, "not a prepared-scans file (version 1)");
  int number = 1;
  while (std::getline(file, text)) {
    ++number;
    if (text.empty() || text[0] == '#') continue;
    std::istringstream line(text);
    std::string key;
    line >> key;
    std::string where = path + ":" + std::to_string(number);
    if (key == "SCAN") {
      if (in.angles.empty()) fail(where, "SCAN before the angles line");
      read_scan(line, in, where);
    } else if (key == "laser_pose") {
      if (!(line >> in.laser[0] >> in.laser[1] >> in.laser[2])) fail(where, "bad laser_pose");
    } else if (key == "angles") {
      size_t n = 0;
      if (!(line >> n) || n < 2) fail(where, "bad angles count");
      in.angles.resize(n);
      for (double& a : in.angles)
        if (!(line >> a)) fail(where, "fewer angles than announced");
    } else {
      std::string value;
      if (!(line >> value)) fail(where, "key without value: " + key);
      in.values[key] = value;
    }
  }
  if (in.times.empty()) fail(path, "no SCAN line");
  return in;
}

double number(const Prepared& in, const std::string& key) {
  std::map<std::string, std::string>::const_iterator it = in.values.find(key);
  if (it == in.values.end()) fail("prepared scans", "missing parameter " + key);
  char* end = 0;
  double v = std::strtod(it->second.c_str(), &end);
  if (*end != '\0') fail("prepared scans", "parameter " + key + " is not a number");
  return v;
}

// a ⊕ b for planar poses (m, rad), angle wrapped to (-pi, pi].
GMapping::OrientedPoint compose(const GMapping::OrientedPoint& a, const GMapping::OrientedPoint& b) {
  double c = std::cos(a.theta), s = std::sin(a.theta);
  double th = std::atan2(std::sin(a.theta + b.theta), std::cos(a.theta + b.theta));
  return GMapping::OrientedPoint(a.x + c * b.x - s * b.y, a.y + s * b.x + c * b.y, th);
}

GMapping::OrientedPoint inverse(const GMapping::OrientedPoint& a) {
  double c = std::cos(a.theta), s = std::sin(a.theta);
  return GMapping::OrientedPoint(-c * a.x - s * a.y, s * a.x - c * a.y, -a.theta);
}

// Records Neff after each scan match (normalize()'s formula, before resampling) and counts
// resamplings, through the processor's hooks.
class Processor : public GMapping::GridSlamProcessor {
 public:
  explicit Processor(std::ostream& info) : GMapping::GridSlamProcessor(info) {}
  int resamples = 0;
  std::vector<double> neff;
  void onResampleUpdate() override { ++resamples; }
  void onScanmatchUpdate() override {
    double gain = 1.0 / (m_obsSigmaGain * m_particles.size()), lmax = -1e300;
    for (const Particle& p : m_particles) lmax = p.weight > lmax ? p.weight : lmax;
    double sum = 0.0, sum_sq = 0.0;
    for (const Particle& p : m_particles) sum += std::exp(gain * (p.weight - lmax));
    for (const Particle& p : m_particles) sum_sq += std::pow(std::exp(gain * (p.weight - lmax)) / sum, 2);
    neff.push_back(1.0 / sum_sq);
  }
};

GMapping::RangeSensor* make_sensor(const Prepared& in, double centre, double max_range) {
  const std::string mode = in.values.count("angle_mode") ? in.values.at("angle_mode") : "node";
  size_t n = in.angles.size();
  double increment = std::fabs(in.angles[n - 1] - in.angles[0]) / double(n - 1);
  GMapping::RangeSensor* sensor = new GMapping::RangeSensor(
      "FLASER", n, increment, GMapping::OrientedPoint(0, 0, 0), 0.0, max_range);
  if (mode == "exact") {
    for (size_t i = 0; i < n; ++i) sensor->beams()[i].pose.theta = in.angles[i] - centre;
    sensor->updateBeamsLookup();
  } else if (mode != "node") {
    fail("prepared scans", "angle_mode must be node or exact, not " + mode);
  }
  return sensor;
}

void configure(Processor& gsp, const Prepared& in, const GMapping::OrientedPoint& start) {
  gsp.setMatchingParameters(number(in, "maxUrange"), number(in, "maxRange"), number(in, "sigma"),
                            int(number(in, "kernelSize")), number(in, "lstep"),
                            number(in, "astep"), int(number(in, "iterations")),
                            number(in, "lsigma"), number(in, "ogain"),
                            (unsigned int)number(in, "lskip"));
  gsp.setMotionModelParameters(number(in, "srr"), number(in, "srt"), number(in, "str"),
                               number(in, "stt"));
  gsp.setUpdateDistances(number(in, "linearUpdate"), number(in, "angularUpdate"),
                         number(in, "resampleThreshold"));
  gsp.setUpdatePeriod(number(in, "temporalUpdate"));
  gsp.setgenerateMap(false);
  gsp.GridSlamProcessor::init((unsigned int)number(in, "particles"), number(in, "xmin"),
                              number(in, "ymin"), number(in, "xmax"), number(in, "ymax"),
                              number(in, "delta"), start);
  gsp.setllsamplerange(number(in, "llsamplerange"));
  gsp.setllsamplestep(number(in, "llsamplestep"));
  gsp.setlasamplerange(number(in, "lasamplerange"));
  gsp.setlasamplestep(number(in, "lasamplestep"));
  gsp.setminimumScore(number(in, "minimumScore"));
}


// Process CPU time (s): the driver is single-threaded, so other load on the machine does not count.
double cpu_seconds() { return double(std::clock()) / CLOCKS_PER_SEC; }

// The map bounds the node keeps between rebuilds (they grow with the map), m.
struct MapBounds {
  double xmin, ymin, xmax, ymax;
};

// slam_gmapping's updateMap without ROS: returns its wall time (s); counts the traversed
// beam cells and the map cells.
double rebuild_map(const Processor& gsp, GMapping::RangeSensor* sensor, const Prepared& in,
                   MapBounds& bounds, size_t& nodes, double& line_cells, double& map_cells) {
  double start = cpu_seconds();
  size_t n = in.angles.size();
  std::vector<double> angles(n);
  for (size_t i = 0; i < n; ++i) angles[i] = sensor->beams()[i].pose.theta;
  GMapping::ScanMatcher matcher;
  matcher.setLaserParameters(n, angles.data(), sensor->getPose());
  matcher.setlaserMaxRange(number(in, "maxRange"));
  matcher.setusableRange(number(in, "maxUrange"));
  matcher.setgenerateMap(true);
  const GMapping::GridSlamProcessor::Particle& best =
      gsp.getParticles()[gsp.getBestParticleIndex()];
  double delta = number(in, "delta"), urange = number(in, "maxUrange");
  GMapping::Point centre((bounds.xmin + bounds.xmax) / 2.0, (bounds.ymin + bounds.ymax) / 2.0);
  GMapping::ScanMatcherMap smap(centre, bounds.xmin, bounds.ymin, bounds.xmax, bounds.ymax, delta);
  nodes = 0;
  line_cells = 0.0;
  for (const GMapping::GridSlamProcessor::TNode* node = best.node; node; node = node->parent) {
    if (!node->reading) continue;
    const double* r = &((*node->reading)[0]);
    matcher.invalidateActiveArea();
    matcher.computeActiveArea(smap, node->pose, r);
    matcher.registerScan(smap, node->pose, r);
    ++nodes;
    for (size_t i = 0; i < n; ++i) line_cells += std::min(r[i], urange) / delta;
  }
  GMapping::Point wmin = smap.map2world(GMapping::IntPoint(0, 0));
  GMapping::Point wmax = smap.map2world(GMapping::IntPoint(smap.getMapSizeX(), smap.getMapSizeY()));
  bounds = MapBounds{wmin.x, wmin.y, wmax.x, wmax.y};
  std::vector<signed char> grid(size_t(smap.getMapSizeX()) * smap.getMapSizeY());
  for (int x = 0; x < smap.getMapSizeX(); ++x)
    for (int y = 0; y < smap.getMapSizeY(); ++y) {
      double occ = smap.cell(GMapping::IntPoint(x, y));
      grid[size_t(y) * smap.getMapSizeX() + x] = occ < 0 ? -1 : (occ > 0.25 ? 100 : 0);
    }
  map_cells = double(grid.size());
  return cpu_seconds() - start;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3 && argc != 4) {
    std::cerr << "usage: " << argv[0] << " PREPARED_SCANS OUT_TRAJECTORY [TIMING_OUT]"
              << std::endl;
    return 2;
  }
  Prepared in = read_prepared(argv[1]);
  size_t n = in.angles.size();
  double centre = 0.5 * (in.angles[0] + in.angles[n - 1]);
  GMapping::OrientedPoint laser(in.laser[0], in.laser[1], in.laser[2]);
  GMapping::OrientedPoint centred = compose(laser, GMapping::OrientedPoint(0, 0, centre));
  double max_range = number(in, "maxRange");

  std::ofstream quiet("/dev/null");
  Processor gsp(quiet);
  GMapping::RangeSensor* sensor = make_sensor(in, centre, max_range);
  GMapping::SensorMap sensors;
  sensors.insert(std::make_pair(sensor->getName(), sensor));
  gsp.setSensorMap(sensors);
  configure(gsp, in, compose(in.odometry[0], centred));
  GMapping::sampleGaussian(1, (unsigned long)number(in, "seed"));

  FILE* timing = argc == 4 ? std::fopen(argv[3], "w") : 0;
  if (argc == 4 && !timing) fail(argv[3], "cannot write");
  if (timing) std::fprintf(timing, "# scan_index time processScan_s map_update_s nodes line_cells map_cells\n");
  double interval = in.values.count("map_update_interval") ? number(in, "map_update_interval") : 5.0;
  MapBounds bounds{number(in, "xmin"), number(in, "ymin"), number(in, "xmax"), number(in, "ymax")};
  double last_rebuild = -1e300;
  std::map<double, size_t> index_of_time;
  for (size_t k = 0; k < in.times.size(); ++k) {
    if (in.ranges[k].size() != n) fail(argv[1], "scan with a different beam count");
    index_of_time[in.times[k]] = k;
    GMapping::RangeReading reading(n, in.ranges[k].data(), sensor, in.times[k]);
    reading.setPose(compose(in.odometry[k], centred));
    double start = cpu_seconds();
    bool processed = gsp.processScan(reading);
    double process_s = cpu_seconds() - start;
    if (!timing || !processed) continue;
    double update_s = 0.0, line_cells = 0.0, map_cells = 0.0;
    size_t nodes = 0;
    if (in.times[k] - last_rebuild > interval) {
      update_s = rebuild_map(gsp, sensor, in, bounds, nodes, line_cells, map_cells);
      last_rebuild = in.times[k];
    }
    std::fprintf(timing, "%zu %.6f %.6f %.6f %zu %.0f %.0f\n", k, in.times[k], process_s, update_s,
                 nodes, line_cells, map_cells);
  }
  if (timing) std::fclose(timing);

  const GMapping::GridSlamProcessor::Particle& best =
      gsp.getParticles()[gsp.getBestParticleIndex()];
  std::vector<const GMapping::GridSlamProcessor::TNode*> nodes;
  for (const GMapping::GridSlamProcessor::TNode* node = best.node; node; node = node->parent)
    if (node->reading) nodes.push_back(node);
  std::string tmp = std::string(argv[2]) + ".tmp";
  FILE* out = std::fopen(tmp.c_str(), "w");
  if (!out) fail(argv[2], "cannot write");
  std::fprintf(out, "# scan_index time x y theta (robot pose, map frame)\n");
  GMapping::OrientedPoint to_base = inverse(centred);
  for (size_t i = nodes.size(); i-- > 0;) {
    double t = nodes[i]->reading->getTime();
    GMapping::OrientedPoint robot = compose(nodes[i]->pose, to_base);
    std::fprintf(out, "%zu %.9f %.9f %.9f %.9f\n", index_of_time.at(t), t, robot.x, robot.y,
                 robot.theta);
  }
  for (double v : gsp.neff) std::fprintf(out, "# neff %.6f\n", v);
  std::fprintf(out, "# summary processed %zu resamples %d best %d\n", nodes.size(),
               gsp.resamples, gsp.getBestParticleIndex());
  std::fclose(out);
  if (std::rename(tmp.c_str(), argv[2]) != 0) fail(argv[2], "cannot rename the output");
  return 0;
}
