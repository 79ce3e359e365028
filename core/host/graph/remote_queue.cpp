#include "graph/remote_queue.hpp"

#include <utility>

#include <spdlog/spdlog.h>

#include "config/error.hpp"

namespace tern::core {

void RemoteQueue::request_param(ParamBase& param, std::string qualified_name, ParamValue value, std::string source) {
  std::lock_guard lk(mu_);
  if (params_.size() >= kMaxQueued)
    throw ConfigError(qualified_name + ": not changed: " + std::to_string(kMaxQueued) +
                      " parameter changes already wait for the next tick (a flood of requests between flights?)");
  params_.push_back({&param, std::move(qualified_name), std::move(value), std::move(source)});
  pending_.store(true, std::memory_order_release);
}

void RemoteQueue::edit_mission(const msg::MissionEdit& edit, bool own) {
  std::lock_guard lk(mu_);
  if (!own && edits_.size() >= kMaxQueued)
    throw ConfigError("mission edit #" + std::to_string(edit.id) + " refused: " + std::to_string(kMaxQueued) +
                      " mission edits already wait for the next ticks (a flood of requests between flights?)");
  edits_.push_back(edit);
  pending_.store(true, std::memory_order_release);
}

std::size_t RemoteQueue::queued_edits() const {
  std::lock_guard lk(mu_);
  return edits_.size();
}

void RemoteQueue::request_go_around(std::string source) {
  std::lock_guard lk(mu_);
  go_around_ = std::move(source);
  go_around_pending_.store(true, std::memory_order_release);
}

std::optional<std::string> RemoteQueue::take_go_around() {
  if (!go_around_pending_.load(std::memory_order_acquire)) return std::nullopt;
  std::lock_guard lk(mu_);
  go_around_pending_.store(false, std::memory_order_relaxed);
  return std::exchange(go_around_, std::nullopt);
}

void RemoteQueue::set_pilot(const msg::Rc& rc) {
  std::lock_guard lk(mu_);
  pilot_ = rc;
  pending_.store(true, std::memory_order_release);
}

const OutputBase* RemoteQueue::renew_pilot_output() {
  pilot_out_ = std::make_unique<Output<msg::Rc>>();
  pilot_out_->set_identity("pilot", "pilot sticks and switches from the console");
  return pilot_out_.get();
}

void RemoteQueue::keep_pilot_output(bool taken) {
  if (!taken) pilot_out_.reset();
}

const OutputBase* RemoteQueue::renew_mission_edit_output() {
  mission_edit_out_ = std::make_unique<Output<msg::MissionEdit>>();
  mission_edit_out_->set_identity("mission_edit", "mission edits from the command line and DDS");
  mission_edit_out_->keep_history(msg::MissionEdit::kQueue);  // a reader stepping less often than the ticks reads each
  return mission_edit_out_.get();
}

void RemoteQueue::keep_mission_edit_output(bool taken) {
  if (!taken) mission_edit_out_.reset();
}

void RemoteQueue::set_value(const ParamRequest& rq) {
  std::lock_guard lk(values_mu_);
  rq.param->set(rq.value);
}

ParamValue RemoteQueue::value_of(const ParamBase& param) const {
  std::lock_guard lk(values_mu_);
  return param.value();
}

void RemoteQueue::apply_before_start(const ParamRecorder& record, spdlog::logger& log) {
  std::lock_guard lk(mu_);
  for (auto rq = params_.begin(); rq != params_.end(); ++rq) {
    try {
      set_value(*rq);
      record(0, rq->name, *rq->param, rq->source);
      log.info("{} = {} ({}, before the start)", rq->name, to_string(rq->param->value()), rq->source);
    } catch (const std::exception& e) {
      log.error("{} not changed: {}", rq->name, e.what());
    }
  }
  params_.clear();
}

void RemoteQueue::apply(Nanos now, const ParamRecorder& record, spdlog::logger& log) {
  if (!pending_.load(std::memory_order_acquire)) return;
  std::vector<ParamRequest> params;
  std::vector<msg::MissionEdit> edits;
  std::optional<msg::Rc> pilot;
  {
    std::lock_guard lk(mu_);
    params.swap(params_);
    edits.swap(edits_);
    pilot.swap(pilot_);
    pending_.store(false, std::memory_order_relaxed);
  }
  if (pilot && pilot_out_) {
    pilot->stamp = now;
    pilot_out_->publish(*pilot);
  }
  // one edit per tick reaches the planner (a port holds the latest message): keep the rest queued
  if (!edits.empty() && !mission_edit_out_) {
    log.warn("t={:.3f} s: {} mission edit(s) dropped: no plugin instance reads topic 'mission_edit' any more", to_seconds(now),
             edits.size());
  } else if (!edits.empty()) {
    msg::MissionEdit e = edits.front();
    e.stamp = now;
    mission_edit_out_->publish(e);
    log.info("t={:.3f} s: mission edit #{} (op {})", to_seconds(now), e.id, static_cast<int>(e.op));
    if (edits.size() > 1) {
      std::lock_guard lk(mu_);
      edits_.insert(edits_.begin(), edits.begin() + 1, edits.end());
      pending_.store(true, std::memory_order_relaxed);
    }
  }
  for (auto& rq : params) {
    try {
      set_value(rq);
      record(now, rq.name, *rq.param, rq.source);
      log.info("t={:.3f} s: {} = {} ({})", to_seconds(now), rq.name, to_string(rq.param->value()), rq.source);
    } catch (const std::exception& e) {
      log.error("t={:.3f} s: {} not changed: {}", to_seconds(now), rq.name, e.what());
    }
  }
}

}  // namespace tern::core
