// libsscape.so is sscape_core linked whole; this translation unit exists because a shared
// library target needs at least one source of its own.
#include <sscape/sscape.h>
