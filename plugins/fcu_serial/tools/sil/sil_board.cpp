// sil/sil_board.cpp: see sil_board.hpp.
#include "sil_board.hpp"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>

namespace tern::fcu::sil {

SilBoard::SilBoard(std::string flash_file) : flash_(std::move(flash_file)) {}

void SilBoard::board_reset(bool bootloader) {
  if (bootloader) std::cerr << "tern-fcu-sil: reboot to bootloader requested: rebooting the firmware instead\n";
  reboot_ = true;
}

std::uint16_t SilBoard::sensors_init_message(char* message, std::uint16_t size, std::uint16_t) {
  if (size > 0) message[0] = '\0';
  return 0;
}

void SilBoard::serial_write(const std::uint8_t* src, std::size_t len, std::uint8_t) { tx_.insert(tx_.end(), src, src + len); }

std::uint16_t SilBoard::serial_bytes_available() { return static_cast<std::uint16_t>(std::min<std::size_t>(rx_.size(), 0xFFFF)); }

std::uint8_t SilBoard::serial_read() {
  if (rx_.empty()) return 0;
  const std::uint8_t b = rx_.front();
  rx_.pop_front();
  return b;
}

std::vector<std::uint8_t> SilBoard::take_sent() {
  std::vector<std::uint8_t> out;
  out.swap(tx_);
  return out;
}

void SilBoard::pwm_init(const float* rate, std::uint32_t channels) {
  pwm_rate_.fill(0.0f);
  for (std::uint32_t i = 0; i < channels && i < kOutputs; ++i) pwm_rate_[i] = rate[i];
  pwm_enabled_ = true;
}

void SilBoard::pwm_disable() {
  pwm_.fill(0.0f);
  pwm_enabled_ = false;
}

void SilBoard::pwm_write(float* value, std::uint32_t channels) {
  if (!pwm_enabled_) return;
  for (std::uint32_t i = 0; i < channels && i < kOutputs; ++i) pwm_[i] = value[i];
}

bool SilBoard::memory_read(void* dest, std::size_t len) {
  std::error_code ec;
  if (flash_.empty() || std::filesystem::file_size(flash_, ec) != len || ec) return false;
  std::ifstream in(flash_, std::ios::binary);
  return static_cast<bool>(in.read(static_cast<char*>(dest), static_cast<std::streamsize>(len)));
}

/// Written beside the file and renamed over it: a crash mid-write leaves the old block.
bool SilBoard::memory_write(const void* src, std::size_t len) {
  if (flash_.empty()) return false;
  const std::string tmp = flash_ + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out.write(static_cast<const char*>(src), static_cast<std::streamsize>(len)) || !out.flush()) {
      std::cerr << "tern-fcu-sil: flash " << flash_ << ": cannot write " << tmp << ": " << std::strerror(errno) << "\n";
      return false;
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, flash_, ec);
  if (ec) std::cerr << "tern-fcu-sil: flash " << flash_ << ": " << ec.message() << "\n";
  return !ec;
}

bool SilBoard::backup_memory_read(void* dest, std::size_t len) {
  if (backup_.size() != len) return false;
  std::memcpy(dest, backup_.data(), len);
  return true;
}

void SilBoard::backup_memory_write(const void* src, std::size_t len) {
  const auto* p = static_cast<const std::uint8_t*>(src);
  backup_.assign(p, p + len);
}

void SilBoard::backup_memory_clear(std::size_t) { backup_.clear(); }

}  // namespace tern::fcu::sil
