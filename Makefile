# tern: front end to CMake. `make fly` and `make test` do the whole set-up on a fresh Debian
# machine (packages, configure, build). See README.md.
BUILD ?= build
JOBS ?= 2
CONFIG ?= configs/missions/default.yaml
CMAKE_ARGS ?=
# ccache (CMakeLists.txt uses it when installed) hashes paths below this folder as relative
# ones, so that a second clone of tern (another folder, CI's) reuses what this one compiled.
export CCACHE_BASEDIR ?= $(CURDIR)

# Every Debian package tern needs to build, test, fly and plot (zstd and zlib: the MCAP flight
# log; clang-format and git: the format
# test; chromium, its driver and selenium:
# the console's and the 3-D replay's browser tests; SDL2: the joystick plugin). npm (Debian's, unless
# one is installed) fetches the console's uPlot and three.js (bundled by esbuild into the 3-D view)
# and the tests' MCAP readers (@mcap/core, @foxglove/rosmsg...).
DEBIAN_PACKAGES := cmake ninja-build ccache g++ make pkg-config \
  libeigen3-dev libpcg-cpp-dev libboost-dev libboost-filesystem-dev libyaml-cpp-dev libspdlog-dev libfmt-dev \
  doctest-dev libcli11-dev nlohmann-json3-dev libgeographiclib-dev libarchive-dev libzstd-dev zlib1g-dev \
  libfastrtps-dev fastddsgen cyclonedds-dev cyclonedds-tools openssl libssl-dev \
  python3 python3-matplotlib python3-numpy python3-yaml python3-distributed \
  pybind11-dev python3-dev python3-pytest \
  chromium chromium-driver python3-selenium libsdl2-dev clang-format git
# Only for `make fuzz` (libFuzzer needs clang and its runtime).
FUZZ_PACKAGES := clang libclang-rt-14-dev
FUZZ_SECONDS ?= 60

.PHONY: all deps install-packages configure build fly campaign test bench fuzz sanitize tsan clean \
  arm64-deps arm64-binfmt arm64 arm64-test arm64-ctest arm64-flight

all: build

# The npm folders: uPlot, three.js and esbuild for the console and tern plot's 3-D replay, Foxglove's MCAP readers and node-mavlink (a ground station)
# for the tests. `npm ci` runs only when a folder's package-lock.json is newer than what it installed
# (npm's own copy of the lock in node_modules/.package-lock.json), so that after the first `make fly`
# tern builds and flies offline.
NPM_DIRS := core/apps/console tests/mcap_reader tests/mavlink
NPM_STAMPS := $(addsuffix /node_modules/.package-lock.json,$(NPM_DIRS))

deps: $(NPM_STAMPS)
	@$(MAKE) --no-print-directory install-packages PACKAGES="$(DEBIAN_PACKAGES)"

%/node_modules/.package-lock.json: %/package-lock.json
	@$(MAKE) --no-print-directory install-packages PACKAGES="$(DEBIAN_PACKAGES)"
	@command -v npm >/dev/null || $(MAKE) --no-print-directory install-packages PACKAGES="npm"
	cd $* && npm ci --no-audit --no-fund
	touch $@

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
	$(BUILD)/bin/tern fly $(CONFIG) --log-dir runs --log-format mcap
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

# The parsers of outside bytes under libFuzzer (clang, ASan+UBSan; docs/hostile-inputs.md,
# "Fuzzing"), JOBS at a time, each FUZZ_SECONDS long: fcu_serial's MAVLink, the MCAP reader,
# the sensor-log tables, the ULog reader, the ground station's datagrams and mission checks, the
# mission config and waypoint files, sensor_log.yaml, the imported text tables and aero files, the
# console's requests, the aircraft file, `tern import`'s archives, the MCAP recovery, the ULog
# conversion into a sensor log, the ground station's mission protocol, QGroundControl's plan files
# (tests/fuzz). Each target's
# corpus grows in $(BUILD)-fuzz/corpus/<target>, seeded from tests/fuzz/corpus/<target>, with
# tests/fuzz/dict/<target>.dict where there is one;
# bench/fuzz_report.py runs them and writes FUZZ_REPORT (executions, CPU seconds, corpus size,
# crashes per target), then fails if any target found something (its input in
# $(BUILD)-fuzz/fuzz_artifacts/<target>).
FUZZ_TARGETS := fuzz_mavlink fuzz_mcap_reader fuzz_csv_table fuzz_ulog_reader fuzz_gcs_datagram fuzz_mission_yaml \
  fuzz_sensor_log_yaml fuzz_text_table fuzz_console_command fuzz_aircraft_yaml fuzz_archive fuzz_mcap_recovery \
  fuzz_ulog_conversion fuzz_mission_protocol fuzz_plan_file fuzz_dataflash fuzz_campaign_file fuzz_dds_request
FUZZ_REPORT ?= bench/results/fuzz.json
fuzz: deps
	@$(MAKE) --no-print-directory install-packages PACKAGES="$(FUZZ_PACKAGES)"
	CXX=clang++ cmake -S . -B $(BUILD)-fuzz -G Ninja -DTERN_PLUGINS=fcu_serial
	cmake --build $(BUILD)-fuzz -j $(JOBS) --target $(FUZZ_TARGETS)
	python3 bench/fuzz_report.py --build $(BUILD)-fuzz --seconds $(FUZZ_SECONDS) --jobs $(JOBS) --out $(FUZZ_REPORT) $(FUZZ_TARGETS)

# Sanitizer builds (issue 78; docs/hostile-inputs.md, "Sanitizers"): `make sanitize` builds every
# target with AddressSanitizer and UndefinedBehaviorSanitizer (GCC, -O1, line tables) in
# $(BUILD)-asan and runs the whole ctest suite there; `make tsan` builds with ThreadSanitizer in
# $(BUILD)-tsan and runs the tests of tern's threaded parts (TSAN_TESTS: the served host and its
# console, the ground station's link, the DDS bridge, the log writer, Python's host, fleets,
# campaigns). A finding stops the process it is in (halt_on_error) and fails its test; the
# suppression files (tests/sanitizers/) name each third-party library and its upstream issue.
# Tests keep their time-outs times SANITIZE_TIMEOUT_SCALE (the instrumented code is slower).
SANITIZE_BUILD ?= $(BUILD)-asan
TSAN_BUILD ?= $(BUILD)-tsan
SANITIZE_TIMEOUT_SCALE ?= 4
SANITIZER_CMAKE_ARGS := -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
  -DTERN_TEST_TIMEOUT_SCALE=$(SANITIZE_TIMEOUT_SCALE)
SANITIZER_DIR := $(CURDIR)/tests/sanitizers
ASAN_ENV := ASAN_OPTIONS=halt_on_error=1:detect_leaks=1:detect_stack_use_after_return=1:strict_string_checks=1 \
  LSAN_OPTIONS=suppressions=$(SANITIZER_DIR)/lsan.supp:print_suppressions=0 \
  UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
TSAN_ENV := TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1:suppressions=$(SANITIZER_DIR)/tsan.supp
TSAN_TESTS ?= served|console|mavlink|gcs|dds|durable_log|mcap|python|fleet|campaign|realtime|swap
# The docs' commands run through bash, which a preloaded ThreadSanitizer runtime crashes, and their
# Python snippets need it preloaded: the python_* tests cover the bindings under TSan instead.
TSAN_EXCLUDE ?= ^docs_
SANITIZE_CTEST_ARGS ?=

sanitize: deps
	cmake -S . -B $(SANITIZE_BUILD) -G Ninja -DTERN_SANITIZE=address,undefined $(SANITIZER_CMAKE_ARGS)
	cmake --build $(SANITIZE_BUILD) -j $(JOBS)
	cd $(SANITIZE_BUILD) && $(ASAN_ENV) ctest --output-on-failure -j $(JOBS) $(SANITIZE_CTEST_ARGS)

tsan: deps
	cmake -S . -B $(TSAN_BUILD) -G Ninja -DTERN_SANITIZE=thread $(SANITIZER_CMAKE_ARGS)
	cmake --build $(TSAN_BUILD) -j $(JOBS)
	cd $(TSAN_BUILD) && $(TSAN_ENV) ctest --output-on-failure -j $(JOBS) -R '$(TSAN_TESTS)' -E '$(TSAN_EXCLUDE)' $(SANITIZE_CTEST_ARGS)

# ---- arm64 (issue 41; docs/companion-computer.md, "Building for arm64") ----------------------
# `make arm64` cross-builds everything for aarch64 into build-arm64 with Debian's cross toolchain
# and its multiarch :arm64 -dev packages (cmake/toolchain-aarch64-linux-gnu.cmake). `make
# arm64-test` then flies the default mission ARM64_SECONDS long under qemu-user and on x86-64
# (ARM64_REFERENCE_TERN; by default this tree's native build, built for the default mission if
# needed) with the same seed, prints the differences (tests/arm64/compare_arch.py) (arm64-flight),
# and runs the tests under qemu-user: ctest minus ARM64_CTEST_EXCLUDE (arm64-ctest). Not part of
# `make test`: it took 84 min to build and 32 min to test here (the doc).
ARM64_BUILD ?= build-arm64
ARM64_SECONDS ?= 60
ARM64_SEED ?= 1
ARM64_MISSION ?= configs/missions/default.yaml
ARM64_REFERENCE_TERN ?= $(BUILD)/bin/tern
ARM64_RUNS ?= $(ARM64_BUILD)/arch_compare
ARM64_CMAKE_ARGS ?=
QEMU_AARCH64 := qemu-aarch64 -L /
# the cross toolchain, qemu-user with its binfmt_misc entry, and the :arm64 libraries (the
# header-only and arch-independent ones, e.g. Eigen, CLI11, doctest, nlohmann-json, are the
# native packages of DEBIAN_PACKAGES)
ARM64_PACKAGES := crossbuild-essential-arm64 qemu-user qemu-user-binfmt \
  libboost-dev:arm64 libboost-filesystem-dev:arm64 libspdlog-dev:arm64 libfmt-dev:arm64 \
  libarchive-dev:arm64 libzstd-dev:arm64 zlib1g-dev:arm64 libssl-dev:arm64 libfastrtps-dev:arm64 \
  libsdl2-dev:arm64 libyaml-cpp0.7:arm64 libgeographiclib23:arm64
ARM64_HOST_PACKAGES := cmake ninja-build ccache make pkg-config python3 fastddsgen \
  libeigen3-dev libpcg-cpp-dev doctest-dev libcli11-dev nlohmann-json3-dev
# -dev packages that are not Multi-Arch: same (apt would remove the amd64 one): unpacked into
# the build tree instead, DEV:RUNTIME (tests/arm64/extra_dev.sh)
ARM64_EXTRA_DEV := libyaml-cpp-dev:libyaml-cpp0.7 libgeographiclib-dev:libgeographiclib23
# ctest -E under qemu (each one's reason: docs/companion-computer.md, "Building for arm64"):
# the out-of-tree plugin build with the host compiler, npm and Chromium, and DDS discovery
# (qemu-user 7.2 refuses Fast DDS's IP_MULTICAST_IF socket option: no participant ever matches)
ARM64_CTEST_EXCLUDE ?= ^(sdk_install|mcap_flight|console_browser|dds|dds_security|cli_dds|dds_cyclone_interop|dds_rosplane_gcs|dds_external_controller)$$

arm64-deps:
	@dpkg --print-foreign-architectures | grep -qx arm64 || { \
	  if [ "$$(id -u)" -ne 0 ]; then echo "arm64: run as root: dpkg --add-architecture arm64 && apt-get update"; exit 1; fi; \
	  echo "arm64: dpkg --add-architecture arm64"; dpkg --add-architecture arm64 && apt-get update -q; }
	@$(MAKE) --no-print-directory install-packages PACKAGES="$(ARM64_HOST_PACKAGES) $(ARM64_PACKAGES)"
	@sh tests/arm64/extra_dev.sh $(ARM64_BUILD)/arm64-dev $(ARM64_EXTRA_DEV)

# Programs that tests start themselves (tern-isolate, tern from scripts) are aarch64 ELF files:
# the kernel hands them to qemu through binfmt_misc (qemu-user-binfmt's entry, registered here
# when systemd-binfmt has not done it, e.g. in a container).
arm64-binfmt:
	@if [ ! -e /proc/sys/fs/binfmt_misc/qemu-aarch64 ]; then \
	  if [ "$$(id -u)" -ne 0 ]; then echo "arm64: aarch64 binfmt_misc entry missing; as root: make arm64-binfmt"; exit 1; fi; \
	  [ -e /proc/sys/fs/binfmt_misc/register ] || mount -t binfmt_misc binfmt_misc /proc/sys/fs/binfmt_misc || \
	    { echo "arm64: cannot mount binfmt_misc (not permitted here)"; exit 1; }; \
	  grep -v '^#' /usr/lib/binfmt.d/qemu-aarch64.conf > /proc/sys/fs/binfmt_misc/register || \
	    { echo "arm64: cannot register qemu-aarch64 in binfmt_misc"; exit 1; }; \
	fi; echo "arm64: binfmt_misc runs aarch64 programs with $$(sed -n 's/^interpreter //p' /proc/sys/fs/binfmt_misc/qemu-aarch64)"

$(ARM64_BUILD)/build.ninja:
	cmake -S . -B $(ARM64_BUILD) -G Ninja -DCMAKE_TOOLCHAIN_FILE=cmake/toolchain-aarch64-linux-gnu.cmake \
	  -DTERN_ARM64_EXTRA_PREFIX=$(abspath $(ARM64_BUILD))/arm64-dev/usr $(ARM64_CMAKE_ARGS)

arm64: arm64-deps $(ARM64_BUILD)/build.ninja
	@start=$$(date +%s); cmake --build $(ARM64_BUILD) -j $(JOBS) && \
	echo "arm64: cross build took $$(( $$(date +%s) - start )) s"

arm64-test: arm64-flight arm64-ctest

arm64-ctest: arm64 arm64-binfmt
	@start=$$(date +%s); cd $(ARM64_BUILD) && ctest --output-on-failure -j $(JOBS) -E '$(ARM64_CTEST_EXCLUDE)'; rc=$$?; \
	echo "arm64: ctest under qemu-user took $$(( $$(date +%s) - start )) s"; exit $$rc

arm64-flight: arm64
	@if [ "$(ARM64_REFERENCE_TERN)" = "$(BUILD)/bin/tern" ]; then \
	  $(MAKE) --no-print-directory configure && cmake --build $(BUILD) -j $(JOBS) --target tern_fly; fi
	rm -rf $(ARM64_RUNS) && mkdir -p $(ARM64_RUNS)/x86-64 $(ARM64_RUNS)/arm64
	@start=$$(date +%s%N); $(ARM64_REFERENCE_TERN) fly $(ARM64_MISSION) --duration $(ARM64_SECONDS) --seed $(ARM64_SEED) -q \
	  --log-dir $(ARM64_RUNS)/x86-64 && echo "arm64: x86-64 flight took $$(( ($$(date +%s%N) - start) / 1000000 )) ms"
	@start=$$(date +%s%N); $(QEMU_AARCH64) $(ARM64_BUILD)/bin/tern fly $(ARM64_MISSION) --duration $(ARM64_SECONDS) --seed $(ARM64_SEED) -q \
	  --log-dir $(ARM64_RUNS)/arm64 && echo "arm64: arm64 flight under qemu-user took $$(( ($$(date +%s%N) - start) / 1000000 )) ms"
	python3 tests/arm64/compare_arch.py $(ARM64_RUNS)/x86-64/*/ $(ARM64_RUNS)/arm64/*/ --json $(ARM64_RUNS)/compare.json

clean:
	rm -rf $(BUILD) $(BUILD)-fuzz $(SANITIZE_BUILD) $(TSAN_BUILD) $(ARM64_BUILD)
