// Messages from the Player (SPEC §5, §6): operator control goes through the control inbox;
// the control path applies it (controller, user data, sender faults, returned pair).
#include <string>
#include <variant>

#include "ocp/invariant.hpp"
#include "streamer_impl.hpp"

namespace ocp {

void StreamerCore::Impl::handle_link_message(LinkMessage&& message) {
  if (auto* control = std::get_if<OperatorControl>(&message)) {
    enqueue_operator_control(std::move(*control));
  } else if (const auto* ping = std::get_if<Ping>(&message)) {
    const std::uint64_t pongs_before = stats.pongs_sent;
    ++stats.pongs_sent;
    send_to_player(Pong{ping->id, ping->sent_at});
    OCP_INVARIANT(stats.pongs_sent == pongs_before + 1, "each ping is answered by exactly one pong");
  } else {
    // Feedback, video and pongs travel the other way; a mis-wired link is our bug, not a peer's.
    logger.warn("ignored a link message of kind {} sent to the Streamer", message.index());
  }
}

void StreamerCore::Impl::enqueue_operator_control(OperatorControl&& message) {
  ++stats.operator_messages_received;
  if (!inbox.push(std::move(message), executor.now()) && !inbox_overflow_logged) {
    // Once per backlog episode: the fault already says the control path is behind.
    inbox_overflow_logged = true;
    logger.warn("control inbox full ({} messages): dropping the oldest",
                streamer::ControlInbox::hard_limit_items);
  }
  if (!control_thread_stalled) drain_inbox();
  evaluate_inbox_fault();
  OCP_INVARIANT(control_thread_stalled || inbox.empty(), "a running control path applies its inbox at once");
  OCP_INVARIANT(inbox.size() <= streamer::ControlInbox::hard_limit_items, "the control inbox stays within its limit");
}

void StreamerCore::Impl::drain_inbox() {
  while (!inbox.empty()) apply_operator_control(inbox.pop());
  inbox_overflow_logged = false;
}

void StreamerCore::Impl::evaluate_inbox_fault() {
  faults.set(FaultId::ControlThreadChannelSlow,
             inbox.slow(executor.now(), config.control_queue_limit, config.control_queue_max_age));
}

void StreamerCore::Impl::apply_operator_control(streamer::QueuedControl&& queued) {
  OperatorControl& message = queued.message;
  operator_message_seen = true;
  last_operator_arrival = queued.arrived_at;
  faults.set(FaultId::NoControlMessage, false);

  // Repeat-last-command: the tick sends whatever was applied last (null stays null).
  operator_controller = std::move(message.controller);
  operator_user_data = std::move(message.client_user_data);
  faults.set(FaultId::OperatorStationHasError, !message.sender_faults.empty());

  const auto check = latency_loop.check_returned(message.returned_ack, executor.now());
  if (check != streamer::ReturnedPairCheck::valid) ++stats.invalid_returned_pairs;
  faults.set(FaultId::InvalidMac, check != streamer::ReturnedPairCheck::valid);
  if (check == streamer::ReturnedPairCheck::invalid && !pair_rejection_reported) {
    report_rejected_pair(*message.returned_ack);
  }
  if (check == streamer::ReturnedPairCheck::valid) {
    pair_rejection_reported = false;   // the episode ends: the next bad pair is news again
    const auto latency = latency_loop.latency(executor.now());
    faults.set(FaultId::HighLatency, latency && *latency > config.latency_limit);
  }
  // The fault set agrees with the inputs this message brought.
  const FaultSet& now_faults = faults.faults();
  OCP_INVARIANT(!now_faults.contains(FaultId::NoControlMessage), "an applied operator message clears NoControlMessage");
  OCP_INVARIANT(now_faults.contains(FaultId::InvalidMac) == (check != streamer::ReturnedPairCheck::valid),
                "InvalidMac is raised exactly when the returned pair is not valid");
  OCP_INVARIANT(now_faults.contains(FaultId::OperatorStationHasError) == !message.sender_faults.empty(),
                "OperatorStationHasError is raised exactly when the operator reports faults");
  OCP_INVARIANT(check != streamer::ReturnedPairCheck::valid || !pair_rejection_reported,
                "a valid pair ends the rejection episode");
  OCP_INVARIANT(last_operator_arrival <= executor.now(), "the latest operator message arrived no later than now");
}

void StreamerCore::Impl::report_rejected_pair(const AckPair& rejected) {
  // Once an episode (until a valid pair is accepted again): a client that alters every pair
  // would otherwise log 100 lines a second, and the first one already says what is wrong.
  pair_rejection_reported = true;
  const PairJudgement judgement = latency_loop.judge_rejected(rejected);
  const std::string hint = describe_rejected_pair(rejected, judgement);
  if (pair_rejections.occurred(executor.now())) {
    logger.warn("latency loop not closed (InvalidMac): {} (logged once; more episodes are summarised every {})", hint,
                format_span(pair_rejections.period()));
  }
  if (events.active()) events.publish(Event{executor.now(), component(), PairRejected{rejected, judgement, hint}});
}

}  // namespace ocp
