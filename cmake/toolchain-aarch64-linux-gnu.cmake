# Cross-build for arm64 (aarch64) on a Debian x86-64 machine, with Debian's cross toolchain and its
# multiarch arm64 libraries (docs/companion-computer.md, "Building for arm64"; `make arm64`):
#
#   dpkg --add-architecture arm64 && apt-get update
#   apt-get install crossbuild-essential-arm64 qemu-user qemu-user-binfmt libboost-dev:arm64 ...
#   cmake -S . -B build-arm64 -G Ninja -DCMAKE_TOOLCHAIN_FILE=cmake/toolchain-aarch64-linux-gnu.cmake
#
# The sysroot is the machine's own root: the arm64 libraries, their CMake packages and pkg-config
# files live in /usr/lib/aarch64-linux-gnu, arch-specific headers in /usr/include/aarch64-linux-gnu
# (both on the cross compiler's default search path), and arch-independent headers (Eigen, CLI11,
# doctest, nlohmann-json, Boost's headers) in /usr/include, shared with the native build.
#
# Two -dev packages are not "Multi-Arch: same" in bookworm (libyaml-cpp-dev, libgeographiclib-dev):
# apt cannot install their :arm64 build next to the amd64 one. `make arm64` downloads them and
# unpacks them into a prefix of the build tree (tests/arm64/extra_dev.sh), named here by
# TERN_ARM64_EXTRA_PREFIX; their runtime libraries (libyaml-cpp0.7:arm64, libgeographiclib23:arm64)
# are ordinary multiarch packages.
#
# ctest runs arm64 test executables through CMAKE_CROSSCOMPILING_EMULATOR (qemu-aarch64 from
# qemu-user). Tests that start arm64 programs themselves (tern fly -> tern-isolate, scripts that run
# tern) need the kernel to hand aarch64 ELF files to qemu: binfmt_misc with qemu-user-binfmt's
# qemu-aarch64 entry (`make arm64-binfmt`).

set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(TERN_ARM64_TRIPLE aarch64-linux-gnu)

set(CMAKE_C_COMPILER ${TERN_ARM64_TRIPLE}-gcc)
set(CMAKE_CXX_COMPILER ${TERN_ARM64_TRIPLE}-g++)
set(CMAKE_LIBRARY_ARCHITECTURE ${TERN_ARM64_TRIPLE})

# Libraries and CMake packages: /usr/lib/aarch64-linux-gnu first (CMAKE_LIBRARY_ARCHITECTURE makes
# find_library and find_package look in <prefix>/lib/aarch64-linux-gnu), never the amd64 directory.
# Programs (python3, fastddsgen, openssl, git, node) are the host's.
set(CMAKE_IGNORE_PATH /usr/lib/x86_64-linux-gnu /lib/x86_64-linux-gnu /usr/lib/x86_64-linux-gnu/cmake)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)

# The unpacked non-multiarch -dev packages (see above).
set(TERN_ARM64_EXTRA_PREFIX "" CACHE PATH
    "prefix holding the unpacked arm64 libyaml-cpp-dev and libgeographiclib-dev (make arm64: <build>/arm64-dev/usr)")
if(TERN_ARM64_EXTRA_PREFIX)
  list(PREPEND CMAKE_PREFIX_PATH ${TERN_ARM64_EXTRA_PREFIX})
endif()

# pkg-config (libzstd): the arm64 .pc files, not the amd64 ones. Read at configure time only.
set(ENV{PKG_CONFIG_LIBDIR} "/usr/lib/${TERN_ARM64_TRIPLE}/pkgconfig:/usr/share/pkgconfig")
set(ENV{PKG_CONFIG_PATH} "")

# Run arm64 executables (ctest, add_custom_command with a target) under qemu-user. The dynamic
# loader and libraries are the multiarch arm64 runtime (libc6:arm64 and the :arm64 library
# packages in /lib/aarch64-linux-gnu, /usr/lib/aarch64-linux-gnu), as on a Debian arm64 board, so
# the prefix is / (TERN_QEMU_LD_PREFIX; qemu's -L, the same as QEMU_LD_PREFIX). The cross
# toolchain's own libc in /usr/aarch64-linux-gnu (-L /usr/aarch64-linux-gnu) also starts a
# program, but its ld.so is a different build (2.36-8cross1) from libc6:arm64's, so children
# started through binfmt_misc (which never see -L) would run on another loader: one runtime for all.
find_program(TERN_QEMU_AARCH64 qemu-aarch64 PATHS /usr/bin NO_DEFAULT_PATH)
if(NOT TERN_QEMU_AARCH64)
  find_program(TERN_QEMU_AARCH64 qemu-aarch64)
endif()
set(TERN_QEMU_LD_PREFIX "/" CACHE PATH "qemu-aarch64 -L: where the arm64 dynamic loader and libraries are looked up")
if(TERN_QEMU_AARCH64)
  set(CMAKE_CROSSCOMPILING_EMULATOR ${TERN_QEMU_AARCH64} -L ${TERN_QEMU_LD_PREFIX})
endif()
