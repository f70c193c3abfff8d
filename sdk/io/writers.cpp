#include "io/writers.hpp"

#include "common/atomic_file.hpp"

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

}  // namespace ssc::io
