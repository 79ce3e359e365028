// Input queues (tern/port.hpp): every message between two steps reaches a consumer that asks for
// them, in order; the latest only otherwise; what a queue cannot hold is counted.
#include <doctest/doctest.h>

#include <vector>

#include "tern/testing/harness.hpp"

using namespace tern;

namespace {

/// Records the stamps its inputs received at each step: `imu` with a queue of 3, `baro` without.
class Sink final : public Plugin {
 public:
  void configure() override {
    declare(imu_, "imu", "queued", Need::required, Queue{3});
    declare(baro_, "baro", "latest only", Need::optional);
  }
  void step(Nanos) override {
    imu.clear();
    baro.clear();
    for (const auto& m : imu_.received()) imu.push_back(m.stamp);
    for (const auto& m : baro_.received()) baro.push_back(m.stamp);
    imu_missed = imu_.missed();
    baro_missed = baro_.missed();
  }
  std::vector<Nanos> imu, baro;
  std::uint64_t imu_missed = 0, baro_missed = 0;

 private:
  Input<msg::Imu> imu_;
  Input<msg::Baro> baro_;
};

msg::Imu imu_at(Nanos t) {
  msg::Imu m;
  m.stamp = t;
  return m;
}
msg::Baro baro_at(Nanos t) {
  msg::Baro m;
  m.stamp = t;
  return m;
}

}  // namespace

TEST_CASE("ports: a queued input receives every message since the previous step, oldest first") {
  auto owned = std::make_unique<Sink>();
  Sink& s = *owned;
  testing::Harness h(std::move(owned), {});
  for (Nanos t : {1, 2}) h.set_input("imu", imu_at(t));
  for (Nanos t : {1, 2}) h.set_input("baro", baro_at(t));
  h.step(10);
  CHECK(s.imu == std::vector<Nanos>{1, 2});
  CHECK(s.baro == std::vector<Nanos>{2});  // no queue: the latest only, the other counted
  CHECK(s.imu_missed == 0);
  CHECK(s.baro_missed == 1);
  h.step(20);  // nothing new
  CHECK(s.imu.empty());
  CHECK(s.baro.empty());
  for (Nanos t : {3, 4, 5, 6, 7}) h.set_input("imu", imu_at(t));
  h.step(30);
  CHECK(s.imu == std::vector<Nanos>{5, 6, 7});  // deeper than the queue: the newest 3
  CHECK(s.imu_missed == 2);
  h.set_input("imu", imu_at(8));
  h.step(40);
  CHECK(s.imu == std::vector<Nanos>{8});  // one per step: as without a queue
  CHECK(s.imu_missed == 0);
}

TEST_CASE("ports: an output's history holds what its deepest reader needs; a copied message skips the ones between") {
  Output<msg::Imu> out;
  Input<msg::Imu> in;
  in.set_queue(Queue{4});
  out.keep_history(in.queue_depth());
  CHECK(out.history_size() == 4);
  out.keep_history(2);  // never shrinks
  CHECK(out.history_size() == 4);
  in.bind(&out);
  for (Nanos t = 1; t <= 3; ++t) out.publish(imu_at(t));
  std::vector<Nanos> got;
  for (const auto& m : in.received()) got.push_back(m.stamp);
  CHECK(got == std::vector<Nanos>{1, 2, 3});
  in.mark_seen();
  const msg::Imu far = imu_at(9);
  out.publish_copy(&far, 9);  // numbers 4-8 never published here
  got.clear();
  for (const auto& m : in.received()) got.push_back(m.stamp);
  CHECK(got == std::vector<Nanos>{9});
  CHECK(in.missed() == 5);
  CHECK(out.message(8) == nullptr);
  out.clear();  // between flights: nothing held
  CHECK(out.message(9) == nullptr);
  in.bind(&out);
  out.publish(imu_at(1));
  got.clear();
  for (const auto& m : in.received()) got.push_back(m.stamp);
  CHECK(got == std::vector<Nanos>{1});
}
