#include "hcpf/core/shared_library.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hcpf {
namespace {

// No libm.so.6 next to the test binary, so the build path (a soname here) is
// the one that loads.
TEST(SharedLibrary, FallsBackToTheBuildPathAndFindsTheSymbol) {
  std::string tried;
  void* cos_address = LoadSymbolNextToExecutable("libm.so.6", "libm.so.6", "cos", &tried);
  ASSERT_NE(cos_address, nullptr) << tried;
  EXPECT_EQ(reinterpret_cast<double (*)(double)>(cos_address)(0.0), 1.0);
  // The executable's folder was tried first and is named.
  EXPECT_NE(tried.find("/libm.so.6: "), std::string::npos) << tried;
}

TEST(SharedLibrary, NamesEveryPlaceTriedWhenTheSymbolIsMissing) {
  std::string tried;
  EXPECT_EQ(LoadSymbolNextToExecutable("libm.so.6", "libm.so.6", "hcpf_no_such_symbol", &tried),
            nullptr);
  EXPECT_NE(tried.find("\n  libm.so.6: no hcpf_no_such_symbol"), std::string::npos) << tried;
  EXPECT_EQ(LoadSymbolNextToExecutable("libhcpf_missing.so", "/nonexistent/libhcpf_missing.so", "x",
                                       &tried),
            nullptr);
  EXPECT_NE(tried.find("/nonexistent/libhcpf_missing.so: "), std::string::npos) << tried;
}

}  // namespace
}  // namespace hcpf
