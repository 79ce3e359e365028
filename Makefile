# tern: front end to CMake. `make fly` and `make test` do the whole set-up on a fresh Debian
# machine (packages, configure, build). See README.md.
BUILD ?= build
JOBS ?= 2
CONFIG ?= configs/missions/default.yaml
CMAKE_ARGS ?=

# Every Debian package tern needs to build, test, fly and plot (zstd and zlib: the MCAP flight
# log; clang-format and git: the format
# test; chromium, its driver and selenium:
# the console's browser test; SDL2: the joystick plugin). npm (Debian's, unless one is
# installed) fetches the console's uPlot and the tests' MCAP readers (@mcap/core, @foxglove/rosmsg...).
DEBIAN_PACKAGES := cmake ninja-build ccache g++ make pkg-config \
  libeigen3-dev libboost-dev libboost-filesystem-dev libyaml-cpp-dev libspdlog-dev libfmt-dev \
  doctest-dev libcli11-dev nlohmann-json3-dev libgeographiclib-dev libarchive-dev libzstd-dev zlib1g-dev \
  libfastrtps-dev fastddsgen cyclonedds-dev cyclonedds-tools openssl libssl-dev \
  python3 python3-matplotlib python3-numpy python3-yaml python3-distributed \
  chromium chromium-driver python3-selenium libsdl2-dev clang-format git
# Only for `make fuzz` (libFuzzer needs clang and its runtime).
FUZZ_PACKAGES := clang libclang-rt-14-dev
FUZZ_SECONDS ?= 60

.PHONY: all deps install-packages configure build fly campaign test bench fuzz clean

all: build

deps:
	@$(MAKE) --no-print-directory install-packages PACKAGES="$(DEBIAN_PACKAGES)"
	@command -v npm >/dev/null || $(MAKE) --no-print-directory install-packages PACKAGES="npm"
	cd core/console && npm ci --no-audit --no-fund   # uPlot for the console (package-lock.json)
	cd tests/mcap_reader && npm ci --no-audit --no-fund   # Foxglove's MCAP readers for the tests (package-lock.json)

install-packages:
	@missing=""; for p in $(PACKAGES); do \
	  dpkg-query -W -f='$${Status}\n' $$p 2>/dev/null | grep -q '^install ok installed$$' || missing="$$missing $$p"; \
	done; \
	if [ -z "$$missing" ]; then echo "deps: all Debian packages present"; exit 0; fi; \
	if [ "$$(id -u)" -ne 0 ]; then \
	  echo "deps: missing Debian packages; run as root:"; \
	  echo "  apt-get update && apt-get install -y --no-install-recommends$$missing"; exit 1; \
	fi; \
	echo "deps: installing$$missing"; \
	export DEBIAN_FRONTEND=noninteractive; \
	apt-get update -q && apt-get install -y -q --no-install-recommends $$missing

$(BUILD)/build.ninja:
	cmake -S . -B $(BUILD) -G Ninja $(CMAKE_ARGS)

configure: deps $(BUILD)/build.ninja

build: configure
	cmake --build $(BUILD) -j $(JOBS)

# The default mission builds only tern, tern-plot and the mission's plugins (target tern_fly,
# CMakeLists.txt); another CONFIG builds everything, as its plugins may be any.
FLY_TARGET := $(if $(filter configs/missions/default.yaml,$(CONFIG)),tern_fly,all)
fly: configure
	cmake --build $(BUILD) -j $(JOBS) --target $(FLY_TARGET)
	$(BUILD)/bin/tern fly $(CONFIG) --log-dir runs
	@run=$$(ls -1dt runs/*/ | head -1); \
	if [ -x $(BUILD)/bin/tern-plot ]; then $(BUILD)/bin/tern-plot $$run; fi; \
	echo "flight log: $$run"; \
	if [ -d $$run/plots ]; then echo "plots:      $$run""plots/"; fi

# The shipped Monte Carlo campaign (200 flights of the default mission over wind, turbulence,
# mass and aero coefficients) on every core: table, summary and plots in campaigns/<name>/.
CAMPAIGN ?= configs/campaigns/hourglass_dispersion.yaml
campaign: build
	$(BUILD)/bin/tern campaign $(CAMPAIGN)

test: build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

bench: build
	cmake --build $(BUILD) --target bench

# The MAVLink parser of fcu_serial under libFuzzer (clang), FUZZ_SECONDS long.
fuzz: deps
	@$(MAKE) --no-print-directory install-packages PACKAGES="$(FUZZ_PACKAGES)"
	CXX=clang++ cmake -S . -B $(BUILD)-fuzz -G Ninja -DTERN_PLUGINS=fcu_serial
	cmake --build $(BUILD)-fuzz -j $(JOBS) --target fuzz_mavlink
	mkdir -p $(BUILD)-fuzz/corpus
	$(BUILD)-fuzz/bin/fuzz_mavlink -max_total_time=$(FUZZ_SECONDS) $(BUILD)-fuzz/corpus

clean:
	rm -rf $(BUILD) $(BUILD)-fuzz
