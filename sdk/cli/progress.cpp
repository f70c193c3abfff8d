#include "progress.hpp"

#include <csignal>
#include <cstdio>
#include <unistd.h>

namespace ssc::cli {
namespace {

// Set by the SIGINT handler: the one thing a signal handler may safely write.
volatile std::sig_atomic_t g_interrupted = 0;

extern "C" void on_interrupt(int) { g_interrupted = 1; }

}  // namespace

Progress::Progress(std::string label)
    : label_(std::move(label)), terminal_(isatty(fileno(stderr)) != 0), start_(std::chrono::steady_clock::now()), last_(start_) {
    g_interrupted = 0;
    previous_ = std::signal(SIGINT, on_interrupt);
}

Progress::~Progress() {
    std::signal(SIGINT, previous_ == SIG_ERR ? SIG_DFL : previous_);
    clear();
}

void Progress::clear() {
    if (shown_) std::fprintf(stderr, "\r\033[K");
    shown_ = false;
}

bool Progress::interrupted() { return g_interrupted != 0; }

bool Progress::update(const std::string& text) {
    const auto now = std::chrono::steady_clock::now();
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    if (terminal_ && elapsed >= 1.0 && (!shown_ || std::chrono::duration<double>(now - last_).count() >= 0.2)) {
        std::fprintf(stderr, "\r\033[K%s: %s (%.0f s; Ctrl-C cancels)", label_.c_str(), text.c_str(), elapsed);
        std::fflush(stderr);
        last_ = now;
        shown_ = true;
    }
    return !interrupted();
}

}  // namespace ssc::cli
