/* A library that says it is the next ABI major and has nothing else: the bindings must refuse it
 * with a message (their ABI check), not crash on a missing or changed function. Built as
 * libsscape.so in its own folder (tests/CMakeLists.txt). */
#include <sscape/sscape.h>

SSC_API uint32_t ssc_version(void) { return (SSC_VERSION_MAJOR + 1) * 10000; }
