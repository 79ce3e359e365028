#include "runners/external_plugin.hpp"

#include <algorithm>
#include <stdexcept>

#include <spdlog/spdlog.h>

#include "tern/msg/control.hpp"
#include "tern/msg/state.hpp"

namespace tern::core {

namespace {

ExternalLinkFactory& factory_slot() {
  static ExternalLinkFactory f;
  return f;
}

// Calls fn(T{}) with the tern message type named `tern_type` (a binding's).
template <class Fn>
void with_type(std::string_view tern_type, Fn&& fn) {
  if (tern_type == msg::State::type_name) return fn(msg::State{});
  if (tern_type == msg::ControllerCommand::type_name) return fn(msg::ControllerCommand{});
  if (tern_type == msg::Actuators::type_name) return fn(msg::Actuators{});
  throw std::logic_error("external module: no tern type " + std::string(tern_type));
}

}  // namespace

void set_external_link_factory(ExternalLinkFactory factory) { factory_slot() = std::move(factory); }
const ExternalLinkFactory& external_link_factory() { return factory_slot(); }

ExternalPlugin::ExternalPlugin(ExternalSpec spec, std::unique_ptr<ExternalLink> link) : spec_(std::move(spec)), link_(std::move(link)) {}

ExternalPlugin::~ExternalPlugin() = default;

void ExternalPlugin::configure() {
  for (const auto& t : spec_.inputs)
    with_type(t.binding->tern_type, [&](auto m) {
      auto port = std::make_unique<Input<decltype(m)>>();
      this->declare(*port, t.port, "DDS " + spec_.dds_name(t) + " (" + std::string(t.binding->ros_type) + ", written by tern)");
      in_.push_back(std::move(port));
    });
  for (const auto& t : spec_.outputs)
    with_type(t.binding->tern_type, [&](auto m) {
      auto port = std::make_unique<Output<decltype(m)>>();
      this->declare(*port, t.port, "DDS " + spec_.dds_name(t) + " (" + std::string(t.binding->ros_type) + ", read by tern)");
      buf_.emplace_back(sizeof(decltype(m)));
      out_.push_back(std::move(port));
    });
}

void ExternalPlugin::start() {
  silent_ = false;
  last_output_.assign(out_.size(), std::nullopt);
  first_sent_.reset();
  exchanges_ = timeouts_ = 0;
  wait_us_total_ = wait_us_max_ = 0;
  if (!link_) return;
  const auto unmatched = link_->wait_matched(std::chrono::seconds(10));
  if (!unmatched.empty()) {
    std::string names;
    for (const auto& n : unmatched) names += (names.empty() ? "" : ", ") + n;
    log().warn("external module: no peer on {} after 10 s (is the node running, on the same domain?)", names);
  }
}

void ExternalPlugin::step(Nanos now) {
  if (!link_) return;
  bool sent = in_.empty();
  for (std::size_t i = 0; i < in_.size(); ++i)
    if (in_[i]->has_value()) {
      link_->publish(i, in_[i]->source()->data(), now);
      sent = true;
    }
  if (sent && !first_sent_) first_sent_ = std::chrono::steady_clock::now();
  exchange_outputs(now);
}

// --realtime: the newest output of each, held while younger than timeout_ms of wall time. Before
// its first output the module has timeout_ms from the first input sent: until then a step
// publishes nothing and is no miss (no output can exist before the module has seen an input).
bool ExternalPlugin::take_latest_outputs(Nanos now) {
  const auto wall = std::chrono::steady_clock::now();
  const auto hold = std::chrono::microseconds(static_cast<std::int64_t>(spec_.timeout_ms * 1000.0));
  bool all = true;
  for (std::size_t o = 0; o < out_.size(); ++o) {
    if (link_->take_latest(o, now, buf_[o].data())) {
      last_output_[o] = wall;
    } else if (!last_output_[o]) {
      if (first_sent_ && wall - *first_sent_ > hold) all = false;
      continue;
    } else if (wall - *last_output_[o] > hold) {
      all = false;
      continue;
    }
    out_[o]->publish_copy(buf_[o].data(), out_[o]->sequence() + 1);  // a held one keeps the stamp of its step
  }
  return all;
}

void ExternalPlugin::exchange_outputs(Nanos now) {
  const auto t0 = std::chrono::steady_clock::now();
  const auto timeout = std::chrono::microseconds(static_cast<std::int64_t>(spec_.timeout_ms * 1000.0));
  bool all = true;
  if (!spec_.lockstep) all = take_latest_outputs(now);
  for (std::size_t o = 0; spec_.lockstep && o < out_.size(); ++o) {
    const auto left = std::max(std::chrono::microseconds(0),
                               timeout - std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now() - t0));
    if (link_->take(o, now, buf_[o].data(), left))
      out_[o]->publish_copy(buf_[o].data(), out_[o]->sequence() + 1);
    else
      all = false;
  }
  const double waited = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count();
  ++exchanges_;
  wait_us_total_ += waited;
  wait_us_max_ = std::max(wait_us_max_, waited);
  if (!all) {
    if (timeouts_ == 0)
      log().warn("t={:.3f} s: external module silent: {} within {} ms", to_seconds(now),
                 spec_.lockstep ? "no output stamped for this tick" : "no output (--realtime: any stamp)", spec_.timeout_ms);
    ++timeouts_;
  } else if (silent_) {
    log().info("t={:.3f} s: external module answers again", to_seconds(now));
  }
  silent_ = !all;
}

std::vector<std::pair<std::string, double>> ExternalPlugin::summary() const {
  return {{"exchanges", static_cast<double>(exchanges_)},
          {"timeouts", static_cast<double>(timeouts_)},
          {"wait_us_mean", exchanges_ ? wait_us_total_ / static_cast<double>(exchanges_) : 0.0},
          {"wait_us_max", wait_us_max_}};
}

}  // namespace tern::core
