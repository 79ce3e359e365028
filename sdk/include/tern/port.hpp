// tern/port.hpp: typed ports. A plugin publishes on an Output<T> and reads an Input<T>.
//
// An output holds the latest message; every input bound to its topic reads that same object
// (no copy on read). Each publish increments the output's sequence number; an input is
// `updated()` when a message arrived since its plugin last stepped. A consumer that runs
// before its producer within a tick (a feedback edge of the port graph) reads the previous
// tick's value. The host binds inputs to outputs by topic name, after checking that both sides
// carry the same message type (name and layout fingerprint, see tern/reflect.hpp).
//
// Several messages between two steps: `get()` is the latest only. An input declared with a
// queue (`declare(imu_, "imu", "...", Need::required, Queue{64})`) reads every message published
// since its plugin's previous step, oldest first, with `received()`: the host makes the topic's
// producer keep its last 64 messages (a ring inside the Output, sized before the flight; no
// allocation while flying). A producer that publishes once per tick and a consumer stepped every
// tick see exactly one message either way. More than the queue's depth between two steps: the
// oldest are gone and `missed()` counts them. An instance in a child process (`isolate: true`)
// and a mirror of another host's topic receive the latest message only (`missed()` counts the rest).
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "tern/export.hpp"
#include "tern/reflect.hpp"
#include "tern/time.hpp"

namespace tern {

/// Identity of a message type: stable name, layout fingerprint, size, and its log columns.
struct MsgType {
  std::string_view name;
  std::uint64_t fingerprint;
  std::size_t size;
  std::vector<reflect::Column> (*columns)();
};

template <class T>
inline constexpr MsgType msg_type_v{T::type_name, reflect::fingerprint<T>(), sizeof(T), &reflect::layout<T>};

class TERN_API PortBase {
 public:
  virtual ~PortBase();
  PortBase(const PortBase&) = delete;
  PortBase& operator=(const PortBase&) = delete;

  const std::string& name() const { return name_; }    ///< port name as the plugin declared it
  const std::string& topic() const { return topic_; }  ///< topic it is bound to (name unless remapped)
  const std::string& description() const { return description_; }
  const MsgType& type() const { return *type_; }

  // host side
  void set_topic(std::string topic) { topic_ = std::move(topic); }
  void set_identity(std::string name, std::string description) {
    name_ = std::move(name);
    topic_ = name_;
    description_ = std::move(description);
  }

 protected:
  explicit PortBase(const MsgType& type) : type_(&type) {}

 private:
  const MsgType* type_;
  std::string name_, topic_, description_;
};

class TERN_API OutputBase : public PortBase {
 public:
  ~OutputBase() override;
  /// Number of messages published so far (0: nothing yet).
  std::uint64_t sequence() const { return seq_; }
  /// The latest message (a T); valid as long as the output exists.
  const void* data() const { return data_; }
  /// The message numbered `seq` (1: the first published; a T) while this output holds it: the
  /// latest always, the ones before it while its history has room (keep_history); nullptr for
  /// any other number. Valid until the next publish.
  const void* message(std::uint64_t seq) const {
    if (seq < oldest() || seq > seq_) return nullptr;
    return seq == seq_ ? data_ : static_cast<const char*>(history_) + (seq % history_size_) * type().size;
  }
  /// The oldest message number message() gives (sequence() + 1 when nothing was published).
  std::uint64_t oldest() const {
    if (seq_ == 0) return 1;
    const std::uint64_t kept = history_size_ > 1 ? history_size_ : 1;
    return std::max(seq_ >= kept ? seq_ - kept + 1 : 1, std::min(history_from_, seq_));
  }
  /// Messages this output holds: the latest and the ones before it (1: the latest only).
  std::size_t history_size() const { return history_size_ > 1 ? history_size_ : 1; }
  /// Host side, before a flight: hold at least the last `n` messages (an input with Queue{n}
  /// reads each of them); never shrinks. The base class holds the latest only (a proxy output).
  virtual void keep_history(std::size_t n) { (void)n; }
  /// Host side (an isolated instance's proxy outputs, a fleet's mirrors): the type().size bytes
  /// at `bytes`, a message copied from elsewhere (reflect::bitwise_copyable types only), become
  /// the latest message, with sequence number `seq`. The messages skipped between the previous
  /// number and `seq` are not held (message() gives nullptr for them).
  void publish_copy(const void* bytes, std::uint64_t seq) {
    std::memcpy(const_cast<void*>(data_), bytes, type().size);
    if (history_size_ > 1) {
      std::memcpy(static_cast<char*>(history_) + (seq % history_size_) * type().size, bytes, type().size);
      if (seq != seq_ + 1) history_from_ = seq;
    }
    seq_ = seq;
  }
  /// Host side, between flights: nothing published yet (sequence 0, a default message), as
  /// after construction, so that a new flight's first consumers see what a fresh host's do.
  void clear() {
    clear_(const_cast<void*>(data_));
    seq_ = 0;
    history_from_ = 0;
  }

 protected:
  OutputBase(const MsgType& type, const void* data, void (*clear)(void*)) : PortBase(type), data_(data), clear_(clear) {}
  /// The derived class's ring of `n` messages: message number s lives in slot s % n. Messages
  /// published before it existed are not in it.
  void set_history(void* ring, std::size_t n) {
    history_ = ring;
    history_size_ = n;
    history_from_ = seq_ + 1;
  }
  const void* data_;
  std::uint64_t seq_ = 0;

 private:
  void (*clear_)(void*);  ///< assigns a default message to *data_
  void* history_ = nullptr;
  std::size_t history_size_ = 0;    ///< slots in *history_ (0: no ring, the latest only)
  std::uint64_t history_from_ = 0;  ///< the oldest number the ring holds a real message for
};

/// A plugin's output port carrying messages of type T.
template <class T>
class Output final : public OutputBase {
 public:
  Output() : OutputBase(msg_type_v<T>, &value_, [](void* v) { *static_cast<T*>(v) = T{}; }) {}
  /// Makes msg the latest message on the topic: O(sizeof(T)) copy (two with a history), no
  /// allocation.
  void publish(const T& msg) {
    value_ = msg;
    ++seq_;
    if (!ring_.empty()) ring_[seq_ % ring_.size()] = msg;
  }
  /// The message last published (a default T before the first publish).
  const T& last() const { return value_; }
  void keep_history(std::size_t n) override {
    if (n <= 1 || n <= ring_.size()) return;
    ring_.assign(n, T{});
    set_history(ring_.data(), ring_.size());
  }

 private:
  T value_{};
  std::vector<T> ring_;  ///< the last messages, when an input has a queue (keep_history)
};

/// Whether an input must have a producer in the port graph.
enum class Need : std::uint8_t { required, optional };

/// How many messages an input can read between two steps of its plugin (Input<T>::received()):
/// 1, the latest only, unless declared otherwise. Depth >= 1.
struct Queue {
  std::uint32_t depth = 1;
};

class TERN_API InputBase : public PortBase {
 public:
  ~InputBase() override;
  bool connected() const { return src_ != nullptr; }
  /// A message has been published on the topic at least once.
  bool has_value() const { return src_ != nullptr && src_->sequence() > 0; }
  /// A message arrived since this plugin's previous step.
  bool updated() const { return src_ != nullptr && src_->sequence() != seen_; }
  Need need() const { return need_; }
  /// Messages this input can read between two steps (Plugin::declare's Queue).
  std::uint32_t queue_depth() const { return depth_; }
  /// Messages published since this plugin's previous step that received() does not give: more
  /// than the queue's depth, or not held by the producer (an isolated instance, a mirror).
  std::uint64_t missed() const {
    const auto [first, end] = unread();
    return updated() ? src_->sequence() - (seen_ < src_->sequence() ? seen_ : 0) - (end - first) : 0;
  }

  // host side
  void set_need(Need n) { need_ = n; }
  void set_queue(Queue q) { depth_ = q.depth > 0 ? q.depth : 1; }
  /// Binds to a producer (nullptr unbinds). The host checks the type first.
  void bind(const OutputBase* src) {
    src_ = src;
    seen_ = 0;
  }
  const OutputBase* source() const { return src_; }
  void mark_seen() {
    if (src_ != nullptr) seen_ = src_->sequence();
  }

 protected:
  explicit InputBase(const MsgType& type) : PortBase(type) {}
  /// The message numbers received() gives: [first, end), at most queue_depth(), oldest first.
  std::pair<std::uint64_t, std::uint64_t> unread() const {
    if (!updated()) return {0, 0};
    const std::uint64_t last = src_->sequence();
    const std::uint64_t after = seen_ < last ? seen_ : 0;  // a producer emptied between flights
    std::uint64_t first = std::max(after + 1, src_->oldest());
    if (last - first + 1 > depth_) first = last - depth_ + 1;
    return {first, last + 1};
  }
  const OutputBase* src_ = nullptr;
  std::uint64_t seen_ = 0;
  Need need_ = Need::required;
  std::uint32_t depth_ = 1;
};

/// The messages an input received since its plugin's previous step, oldest first (a range for
/// `for (const T& m : in.received())`); valid during the step that asked for it.
template <class T>
class Received {
 public:
  class iterator {
   public:
    iterator(const OutputBase* src, std::uint64_t seq) : src_(src), seq_(seq) {}
    const T& operator*() const { return *static_cast<const T*>(src_->message(seq_)); }
    iterator& operator++() {
      ++seq_;
      return *this;
    }
    bool operator!=(const iterator& o) const { return seq_ != o.seq_; }
    bool operator==(const iterator& o) const { return seq_ == o.seq_; }

   private:
    const OutputBase* src_;
    std::uint64_t seq_;
  };
  Received(const OutputBase* src, std::uint64_t first, std::uint64_t end) : src_(src), first_(first), end_(end) {}
  iterator begin() const { return {src_, first_}; }
  iterator end() const { return {src_, end_}; }
  std::size_t size() const { return static_cast<std::size_t>(end_ - first_); }
  bool empty() const { return end_ == first_; }

 private:
  const OutputBase* src_;
  std::uint64_t first_, end_;
};

/// A plugin's input port reading messages of type T.
template <class T>
class Input final : public InputBase {
 public:
  Input() : InputBase(msg_type_v<T>) {}
  /// The latest message on the topic, or a default-constructed T if there is none yet.
  const T& get() const { return has_value() ? *static_cast<const T*>(src_->data()) : fallback_; }
  const T& operator*() const { return get(); }
  const T* operator->() const { return &get(); }
  /// Every message published since this plugin's previous step, oldest first, up to the queue's
  /// depth (the newest ones; missed() counts the others); empty when not updated(). With the
  /// default depth of 1: the latest, when updated().
  Received<T> received() const {
    const auto [first, end] = unread();
    return {src_, first, end};
  }

 private:
  T fallback_{};
};

}  // namespace tern
