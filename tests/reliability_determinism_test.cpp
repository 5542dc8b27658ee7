// Determinism: every case of the default matrix (`parity run --scene default`), rendered three
// times on one device, gives the same bytes. A nondeterministic render would make every golden
// comparison a coin toss, so this is checked for each backend over the whole matrix.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "harness/run/run.h"
#include "platforms/common/platform.h"
#include "techniques/frame.h"
#include "tests/test_support.h"

using namespace parity;

namespace {

class Determinism : public ::testing::TestWithParam<std::string> {};

TEST_P(Determinism, DefaultMatrixRendersBitIdenticallyThreeTimes) {
  harness::RunFilters filters;
  filters.scenes = {"default"};
  filters.backends = {GetParam()};
  std::string error;
  std::vector<harness::CaseKey> cases = harness::enumerateCases(filters, harness::Shard{}, &error);
  ASSERT_TRUE(error.empty()) << error;
  ASSERT_FALSE(cases.empty());

  auto dev = test::makeDevice(GetParam());
  if (!dev) return;
  int rendered = 0;
  for (const harness::CaseKey& key : cases) {
    if (!harness::platformHasRenderPath(key.platform)) continue;  // Skip in the matrix as well
    techniques::FrameRequest request;
    request.technique = key.technique;
    request.scene = key.scene;
    auto platform = platforms::platformFromName(key.platform);
    ASSERT_TRUE(platform.has_value()) << key.platform;
    request.platform = *platform;
    std::vector<uint8_t> first;
    for (int i = 0; i < 3; ++i) {
      techniques::FrameResult r = techniques::renderFrameTexels(*dev, request);
      ASSERT_TRUE(r.ok) << key.id() << ": " << r.error;
      ASSERT_EQ(r.texels.size(), size_t(request.width) * request.height * 4) << key.id();
      if (i == 0) {
        first = std::move(r.texels);
        continue;
      }
      size_t differing = 0;
      for (size_t b = 0; b < first.size(); ++b) differing += first[b] != r.texels[b];
      EXPECT_EQ(differing, 0u) << key.id() << ": render " << i + 1 << " differs from the first in " << differing
                               << " bytes";
    }
    ++rendered;
  }
  EXPECT_GT(rendered, 0) << "the default matrix rendered nothing";
}

INSTANTIATE_TEST_SUITE_P(Backends, Determinism, ::testing::ValuesIn(test::allBackends()), test::BackendName{});

}  // namespace
