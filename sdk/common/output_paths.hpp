// Outputs never replace inputs: the check every tool that writes files makes before any work.
#pragma once

#include "common/error.hpp"

#include <string>
#include <vector>

namespace ssc {

// Throws ssc::Error(SSC_ERROR_INVALID_ARGUMENT) when `output` names the file of one of `inputs`: the
// same path, another spelling of it, or a symbolic or hard link to it. A tool never replaces what it
// reads (`register scan.ply -o scan.ply` once replaced the raw scan). Empty names are skipped; an
// output that does not exist yet is no input.
void refuse_output_over_input(const std::string& output, const std::vector<std::string>& inputs);

// The files one command writes, all or none. Made before the work: each file's folder is checked by
// creating (and removing) a file in it, so an unwritable path fails at once (SSC_ERROR_IO naming
// it) instead of after minutes of work. Destroyed before keep(), it removes every listed file
// this command wrote (a file that is new, or replaced since: a new inode; writes are atomic
// renames), so a failure between two outputs leaves none of them, and a file that was there and
// was not touched stays. Empty paths are skipped.
class OutputFiles {
public:
    explicit OutputFiles(const std::vector<std::string>& paths);
    ~OutputFiles();
    OutputFiles(const OutputFiles&) = delete;
    OutputFiles& operator=(const OutputFiles&) = delete;
    void keep() { kept_ = true; }  // every output written: they stay

private:
    struct Before {
        std::string path;
        bool existed = false;
        unsigned long long device = 0, inode = 0;
    };
    std::vector<Before> files_;
    bool kept_ = false;
};

}  // namespace ssc
