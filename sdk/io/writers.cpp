#include "io/writers.hpp"

#include "common/files.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace ssc::io {

void write_lnd(const std::string& path, const std::string& subject, const std::vector<LandmarkRecord>& landmarks) {
    std::ostringstream s;
    s << "SUBJECT_ID = " << subject << "\nSCAN_TYPE = sscape simulate\nSTD_LAND = 0\nAUX_LAND = " << landmarks.size() << "\nAUX =\n";
    char line[256];
    for (const auto& l : landmarks) {
        const Eigen::Vector3d mm = l.position * 1000.0;
        std::snprintf(line, sizeof line, "%3u   0  %3u %8.2f %8.2f %8.2f %8.2f %s\n", l.index, l.index, 0.0, mm.x(), mm.y(), mm.z(),
                      l.name.c_str());
        s << line;
    }
    s << "END =\n";
    const std::string text = s.str();
    write_file_atomically(path, text.data(), text.size());
}

void write_pgm_depth(const std::string& path, const DepthImage& img) {
    std::ostringstream s;
    s.precision(17);
    s << "P5\n";
    if (img.has_intrinsics) s << "# sscape intrinsics " << img.fx << ' ' << img.fy << ' ' << img.cx << ' ' << img.cy << "\n";
    if (img.has_pose) {
        s << "# sscape camera_to_world";
        for (int i = 0; i < 16; ++i) s << ' ' << img.camera_to_world(i % 4, i / 4);
        s << "\n";
    }
    s << img.width << ' ' << img.height << "\n65535\n";
    std::string text = s.str();
    const std::size_t header = text.size();
    text.resize(header + 2 * img.depth.size());
    for (std::size_t i = 0; i < img.depth.size(); ++i) {
        const double mm = std::round(double(img.depth[i]) * 1000.0);
        const uint16_t v = std::isfinite(mm) && mm > 0 && mm <= 65535 ? uint16_t(mm) : 0;
        text[header + 2 * i] = char(v >> 8);  // PGM samples are big-endian
        text[header + 2 * i + 1] = char(v & 0xFF);
    }
    write_file_atomically(path, text.data(), text.size());
}

}  // namespace ssc::io
