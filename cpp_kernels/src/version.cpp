#include "wingcrack/version.hpp"
namespace wingcrack { const char* kernels_version() { return "0.1.0"; } }
