#pragma once
namespace wingcrack { const char* kernels_version(); }
