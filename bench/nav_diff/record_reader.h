// A binary record file of bench/nav_diff's captures (formats/nav_cycles.py): 8 magic bytes,
// then native little-endian fields read in order. Any error prints "<program>: <what>" and
// exits with status 2.
#pragma once

#include <costmap_2d/costmap_2d.h>
#include <zlib.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string>
#include <vector>

class RecordReader {
 public:
  // program: the prefix of error lines; magic: the file's 8 first bytes; kind: the records'
  // name in error lines ("cycles", "plans").
  RecordReader(const std::string& path, const char* magic, const std::string& kind,
               const std::string& program)
      : kind_(kind), program_(program) {
    std::ifstream in(path, std::ios::binary);
    if (!in) Fail(path + ": cannot open");
    data_.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    if (data_.size() < 8 || std::memcmp(data_.data(), magic, 8) != 0)
      Fail(path + ": not a captured-" + kind + " file");
    at_ = 8;
  }
  template <typename T>
  T Get() {
    if (at_ + sizeof(T) > data_.size()) Fail(kind_ + ": truncated");
    T value;
    std::memcpy(&value, data_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return value;
  }
  // A costmap record: size x, size y (cells), resolution (m), origin x, y (m), then the
  // zlib-compressed cost bytes; the costmap is resized to it (resizeMap sets the origin
  // exactly, where updateOrigin would snap it to whole cells).
  void ReadCostmap(costmap_2d::Costmap2D& costmap) {
    uint32_t sx = Get<uint32_t>(), sy = Get<uint32_t>();
    double res = Get<double>(), ox = Get<double>(), oy = Get<double>();
    uint32_t n = Get<uint32_t>();
    const unsigned char* packed = Take(n);
    costmap.resizeMap(sx, sy, res, ox, oy);
    uLongf size = static_cast<uLongf>(sx) * sy;
    if (uncompress(costmap.getCharMap(), &size, packed, n) != Z_OK || size != uLongf(sx) * sy)
      Fail(kind_ + ": bad costmap record");
  }
  const unsigned char* Take(size_t n) {
    if (at_ + n > data_.size()) Fail(kind_ + ": truncated");
    const unsigned char* p = reinterpret_cast<const unsigned char*>(data_.data()) + at_;
    at_ += n;
    return p;
  }

 private:
  [[noreturn]] void Fail(const std::string& what) const {
    std::cerr << program_ << ": " << what << std::endl;
    std::exit(2);
  }
  std::vector<char> data_;
  size_t at_ = 0;
  std::string kind_, program_;
};
