// Progress of long commands on a terminal, and Ctrl-C as a clean cancel.
//
// A command that may run longer than a second makes a Progress and calls update() from its
// progress callback: after the first second, on a terminal (stderr), one line is redrawn at most
// five times a second; when stderr is not a terminal nothing is printed. While a Progress lives,
// Ctrl-C does not kill the process: interrupted() turns true, the callback returns "stop", the
// library cancels (SSC_ERROR_CANCELLED) and the command leaves without writing results.
#pragma once

#include <chrono>
#include <string>

namespace ssc::cli {

class Progress {
public:
    explicit Progress(std::string label);
    ~Progress();  // clears the line and restores the previous Ctrl-C handling
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;

    // Shows "label: text (N s)"; returns false once Ctrl-C was pressed.
    bool update(const std::string& text);
    static bool interrupted();
    // Clears the line, so that a line of output can be printed; the next update() draws it again.
    void clear();

private:
    std::string label_;
    bool terminal_, shown_ = false;
    std::chrono::steady_clock::time_point start_, last_;
    void (*previous_)(int) = nullptr;
};

}  // namespace ssc::cli
