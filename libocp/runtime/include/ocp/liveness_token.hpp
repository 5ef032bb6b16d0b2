#pragma once
// LivenessToken: lets a callback that may fire after its owner is destroyed (a timer, a socket
// handler) find out, instead of touching freed memory. The owner holds the token; each callback
// captures a Watch and returns early once `alive()` is false. The owner calls `revoke()` first
// thing in its destructor, so callbacks queued behind it become no-ops.
#include <memory>

namespace ocp {

class LivenessToken {
 public:
  class Watch {
   public:
    [[nodiscard]] bool alive() const { return !flag_.expired(); }

   private:
    friend class LivenessToken;
    explicit Watch(std::weak_ptr<const char> flag) : flag_(std::move(flag)) {}
    std::weak_ptr<const char> flag_;
  };

  [[nodiscard]] Watch watch() const { return Watch(flag_); }
  void revoke() { flag_.reset(); }

 private:
  std::shared_ptr<const char> flag_ = std::make_shared<const char>('\0');
};

}  // namespace ocp
