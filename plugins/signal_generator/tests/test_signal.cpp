// The waveforms of signal.hpp, alone.
#include <doctest/doctest.h>

#include "tern/signal_generator/signal.hpp"

using namespace tern::signal;

TEST_CASE("every waveform starts at 0 and is 0 before its start") {
  for (auto w : {Waveform::step, Waveform::square, Waveform::sine, Waveform::triangle, Waveform::sawtooth, Waveform::doublet}) {
    CHECK(waveform(w, 0.0, 4.0) == doctest::Approx(0.0));
    CHECK(waveform(w, -1.0, 4.0) == 0.0);
  }
}

TEST_CASE("step and square have their first edge at half a period; the square repeats") {
  CHECK(waveform(Waveform::step, 1.99, 4.0) == 0.0);
  CHECK(waveform(Waveform::step, 2.0, 4.0) == 1.0);
  CHECK(waveform(Waveform::step, 100.0, 4.0) == 1.0);
  CHECK(waveform(Waveform::square, 1.99, 4.0) == 0.0);
  CHECK(waveform(Waveform::square, 3.99, 4.0) == 1.0);
  CHECK(waveform(Waveform::square, 4.01, 4.0) == 0.0);
  CHECK(waveform(Waveform::square, 6.01, 4.0) == 1.0);
}

TEST_CASE("sine, triangle and sawtooth peak where ROSplane's do") {
  CHECK(waveform(Waveform::sine, 2.0, 4.0) == doctest::Approx(1.0));
  CHECK(waveform(Waveform::sine, 1.0, 4.0) == doctest::Approx(0.5));
  CHECK(waveform(Waveform::triangle, 2.0, 4.0) == doctest::Approx(1.0));
  CHECK(waveform(Waveform::triangle, 3.0, 4.0) == doctest::Approx(0.5));
  CHECK(waveform(Waveform::sawtooth, 3.0, 4.0) == doctest::Approx(0.75));
  CHECK(waveform(Waveform::sawtooth, 4.5, 4.0) == doctest::Approx(0.125));
}

TEST_CASE("a doublet is one pulse up, one down, then nothing") {
  CHECK(waveform(Waveform::doublet, 1.0, 4.0) == 0.0);
  CHECK(waveform(Waveform::doublet, 3.0, 4.0) == 1.0);
  CHECK(waveform(Waveform::doublet, 5.0, 4.0) == -1.0);
  CHECK(waveform(Waveform::doublet, 6.0, 4.0) == 0.0);
  CHECK(waveform(Waveform::doublet, 60.0, 4.0) == 0.0);
}

TEST_CASE("names round-trip; unknown names are refused") {
  for (auto l : {Loop::roll, Loop::pitch, Loop::course, Loop::altitude, Loop::airspeed}) CHECK(loop_from_name(loop_name(l)) == l);
  CHECK(!loop_from_name("yaw_rate"));
  CHECK(!waveform_from_name("chirp"));
  CHECK(command_symbol(Loop::altitude) == "h_c");
  CHECK(loop_unit(Loop::airspeed) == "m/s");
}
