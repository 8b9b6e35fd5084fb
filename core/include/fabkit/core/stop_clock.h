#pragma once
/// A deadline shared by the steps of one piece of work, which a step may also call early.
///
/// Some steps cannot be interrupted once started (an eigendecomposition of a few hundred
/// motions takes milliseconds), so checking the clock between them lets the work overrun by
/// one such step. A step that knows roughly what it costs asks would_pass() first: if it would
/// end past the deadline it is not started, and the deadline counts as reached from then on,
/// for every later check of the same work — so the work stops once, before its deadline, and
/// reports that it stopped rather than a result it did not finish.

#include <atomic>
#include <chrono>
#include <memory>
#include <optional>

namespace fabkit {

/// Whether `deadline` has passed (none: it never does).
inline bool deadline_passed(const std::optional<std::chrono::steady_clock::time_point>& deadline) {
  return deadline && std::chrono::steady_clock::now() > *deadline;
}

class StopClock {
 public:
  using Clock = std::chrono::steady_clock;

  explicit StopClock(std::optional<Clock::time_point> at = std::nullopt) : at_(at) {}

  /// A clock for work started beside other work, speculatively: it stops when `parent` does
  /// (which may be null) and when whoever started the work calls it off.
  explicit StopClock(std::shared_ptr<const StopClock> parent) : parent_(std::move(parent)) {}

  /// Past the deadline, or called early by a step that could not have finished before it (or
  /// called off).
  bool passed() const {
    if (called_.load(std::memory_order_relaxed)) return true;
    if (parent_) return parent_->passed();
    return deadline_passed(at_);
  }

  /// Whether work expected to take `cost` would end past the deadline. If it would, the
  /// deadline is called now: passed() is true from here on.
  bool would_pass(Clock::duration cost) const {
    if (called_.load(std::memory_order_relaxed)) return true;
    if (parent_) return parent_->would_pass(cost);
    if (!at_) return false;
    if (passed()) return true;
    if (Clock::now() + cost <= *at_) return false;
    called_.store(true, std::memory_order_relaxed);
    return true;
  }

  /// The work this clock times is no longer wanted: passed() is true from here on.
  void call_off() const { called_.store(true, std::memory_order_relaxed); }

 private:
  std::optional<Clock::time_point> at_;
  std::shared_ptr<const StopClock> parent_;
  mutable std::atomic<bool> called_{false};
};

}  // namespace fabkit
