#include <gtest/gtest.h>
#include <string>
#include "wingcrack/version.hpp"
TEST(Version, NonEmpty) { EXPECT_FALSE(std::string(wingcrack::kernels_version()).empty()); }
