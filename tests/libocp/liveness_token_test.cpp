#include "ocp/liveness_token.hpp"

#include <gtest/gtest.h>

#include <memory>

namespace ocp {
namespace {

TEST(LivenessToken, AWatchSeesItsOwnerAliveUntilRevoked) {
  LivenessToken token;
  const LivenessToken::Watch watch = token.watch();
  EXPECT_TRUE(watch.alive());
  token.revoke();
  EXPECT_FALSE(watch.alive());
  EXPECT_FALSE(token.watch().alive());  // a watch taken after revoke is never alive
}

TEST(LivenessToken, ACallbackQueuedBehindItsDestroyedOwnerDoesNothing) {
  int calls = 0;
  struct Owner {
    LivenessToken liveness;
    ~Owner() { liveness.revoke(); }
  };
  auto owner = std::make_unique<Owner>();
  const auto callback = [&calls, watch = owner->liveness.watch()] {
    if (watch.alive()) ++calls;
  };
  callback();
  EXPECT_EQ(calls, 1);
  owner.reset();
  callback();
  EXPECT_EQ(calls, 1);
}

}  // namespace
}  // namespace ocp
