// bench_dds: what one hop costs, in-process port vs Fast DDS on loopback. Prints a table and writes
// bench/results/bench_dds.json.
//   1. port hop: Output<State>::publish -> Input<State>::get (copy of the message), per message
//   2. DDS hop: tern State -> rosplane_msgs State (the bridge's conversion) -> DataWriter::write
//      -> DataReader listener in a second loopback-only participant of this process, best-effort
//      as the bridge's telemetry; State at 400 Hz (wall-paced), publish-to-receive latency median
//      and p99, and the share of samples delivered
//   3. DDS throughput: State written back to back (best-effort), samples received per second
#include <algorithm>
#include <atomic>
#include <chrono>
#include <fstream>
#include <mutex>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "dds_internal.hpp"
#include "rosplane_msgs/msg/StatePubSubTypes.h"
#include "tern/msg/state.hpp"
#include "tern/port.hpp"

using clk = std::chrono::steady_clock;
using namespace tern::core;
namespace fdds = eprosima::fastdds::dds;

namespace {

std::int64_t now_ns() { return std::chrono::duration_cast<std::chrono::nanoseconds>(clk::now().time_since_epoch()).count(); }

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(p * static_cast<double>(v.size())))];
}

class Receiver final : public fdds::DataReaderListener {
 public:
  void on_data_available(fdds::DataReader* r) override {
    rosplane_msgs::msg::State s;
    fdds::SampleInfo info;
    while (r->take_next_sample(&s, &info) == ReturnCode_t::RETCODE_OK) {
      if (!info.valid_data) continue;
      const std::int64_t t = now_ns();
      // the sender's steady clock travels in the header stamp
      const std::int64_t sent = static_cast<std::int64_t>(s.header().stamp().sec()) * 1000000000 + s.header().stamp().nanosec();
      std::lock_guard lk(mu);
      if (recording) latencies.push_back(static_cast<double>(t - sent));
      ++received;
    }
  }
  std::mutex mu;
  std::vector<double> latencies;
  bool recording = true;
  std::atomic<long> received{0};
};

}  // namespace

int main() {
  nlohmann::json out;
  // 1. port hop
  {
    tern::Output<tern::msg::State> o;
    tern::Input<tern::msg::State> in;
    in.bind(&o);
    tern::msg::State m;
    std::vector<double> lat;
    const int n = 200000;
    lat.reserve(n);
    double sink = 0;
    for (int k = 0; k < n; ++k) {
      m.p_n = k;
      const auto t0 = clk::now();
      o.publish(m);
      if (in.updated()) {
        const tern::msg::State copy = in.get();
        sink += copy.p_n;
      }
      in.mark_seen();
      lat.push_back(std::chrono::duration<double, std::nano>(clk::now() - t0).count());
    }
    out["port_hop"] = {{"median_ns", percentile(lat, 0.5)}, {"p99_ns", percentile(lat, 0.99)}, {"samples", n}};
    if (sink < 0) std::puts("");
  }
  // 2. + 3. DDS hop
  DdsOptions opt;
  opt.domain = 97;
  auto* pw = ddsi::make_participant(opt, "bench writer");
  auto* pr = ddsi::make_participant(opt, "bench reader");
  auto* pub = pw->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
  auto* sub = pr->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
  auto* tw = ddsi::make_topic<rosplane_msgs::msg::StatePubSubType>(pw, "rt/tern/state");
  auto* tr = ddsi::make_topic<rosplane_msgs::msg::StatePubSubType>(pr, "rt/tern/state");
  auto* writer = pub->create_datawriter(tw, ddsi::writer_qos(DdsQos::best_effort));
  Receiver rx;
  fdds::DataReaderQos rq = ddsi::reader_qos(DdsQos::best_effort);
  rq.history().depth = 100;
  auto* reader = sub->create_datareader(tr, rq, &rx);
  if (writer == nullptr || reader == nullptr) {
    std::fprintf(stderr, "bench_dds: cannot create the DDS entities\n");
    return 1;
  }
  ddsi::wait_until(
      [&] {
        fdds::PublicationMatchedStatus s;
        writer->get_publication_matched_status(s);
        return s.current_count > 0;
      },
      std::chrono::seconds(10));
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  const auto* type = ddsi::find_type("tern/State");
  auto sample = type->make_sample();
  auto send = [&](tern::msg::State& m) {
    m.stamp = now_ns();
    type->convert(&m, sample.get(), 0, [&] { writer->write(sample.get()); });
  };
  tern::msg::State m;
  m.Va = 15;
  const int n400 = 2000;  // 5 s at 400 Hz
  const auto period = std::chrono::nanoseconds(2500000);
  auto next = clk::now();
  std::vector<double> write_ns;
  for (int k = 0; k < n400; ++k) {
    next += period;
    std::this_thread::sleep_until(next);
    m.p_n = k;
    const auto t0 = clk::now();
    send(m);
    write_ns.push_back(std::chrono::duration<double, std::nano>(clk::now() - t0).count());
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  std::vector<double> lat;
  {
    std::lock_guard lk(rx.mu);
    lat = rx.latencies;
    rx.recording = false;
  }
  out["dds_hop_400hz"] = {{"median_ns", percentile(lat, 0.5)},
                          {"p99_ns", percentile(lat, 0.99)},
                          {"write_median_ns", percentile(write_ns, 0.5)},
                          {"sent", n400},
                          {"received", static_cast<long>(lat.size())}};
  // 3. throughput
  const long before = rx.received.load();
  const int burst = 50000;
  const auto t0 = clk::now();
  for (int k = 0; k < burst; ++k) send(m);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const double secs = std::chrono::duration<double>(clk::now() - t0).count() - 0.3;
  const long got = rx.received.load() - before;
  out["dds_throughput"] = {{"sent", burst}, {"received", got}, {"write_rate_hz", burst / secs}};
  ddsi::delete_participant(pr);
  ddsi::delete_participant(pw);

  fmt::print("bench_dds: one hop of tern/State (rosplane_msgs State on the wire), loopback-only participants\n");
  fmt::print("{:<44} {:>12} {:>12}\n", "", "median", "p99");
  fmt::print("{:<44} {:>9.0f} ns {:>9.0f} ns\n", "in-process port (publish + get + copy)", out["port_hop"]["median_ns"].get<double>(),
             out["port_hop"]["p99_ns"].get<double>());
  fmt::print("{:<44} {:>9.1f} us {:>9.1f} us\n", "Fast DDS UDP loopback at 400 Hz (write->take)", percentile(lat, 0.5) * 1e-3,
             percentile(lat, 0.99) * 1e-3);
  fmt::print("{:<44} {:>9.1f} us\n", "  of which convert + write (flight thread)", percentile(write_ns, 0.5) * 1e-3);
  fmt::print("delivered at 400 Hz: {}/{}; back-to-back: {} of {} written at {:.0f} Hz received\n", lat.size(), n400, got, burst,
             burst / secs);
  const std::filesystem::path dir = TERN_BENCH_RESULTS_DIR;
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "bench_dds.json") << out.dump(2) << "\n";
  return 0;
}
