// One run at a time per output folder: two runs writing one folder would each report success while
// the folder keeps a mix, or only the last one's result (two bootstraps into one folder once both
// said "wrote model.sscape"; the first user's model was gone).
#pragma once

#include <string>

namespace ssc {

// Holds an exclusive advisory lock (flock) on FOLDER/.sscape-lock while it lives, creating the
// folder when needed; a folder it created and nothing else wrote into is removed again with the
// lock (a refused run leaves nothing). The kernel drops the lock when the process ends however it
// ends, so a killed run never leaves the folder locked. Throws ssc::Error (SSC_ERROR_IO) when another process (or
// another lock in this one) holds it, naming the folder and the holder's process id; `what` names
// the run in the message ("bootstrap").
class FolderLock {
public:
    FolderLock(const std::string& folder, const std::string& what);
    ~FolderLock();
    FolderLock(const FolderLock&) = delete;
    FolderLock& operator=(const FolderLock&) = delete;

private:
    std::string folder_, path_;
    bool created_ = false;  // the folder did not exist before
    int fd_ = -1;
};

}  // namespace ssc
