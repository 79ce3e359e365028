// tern/port.hpp: typed ports. A plugin publishes on an Output<T> and reads an Input<T>.
//
// An output holds the latest message; every input bound to its topic reads that same object
// (no copy on read, no queue). Each publish increments the output's sequence number; an input
// is `updated()` when a message arrived since its plugin last stepped. A consumer that runs
// before its producer within a tick (a feedback edge of the port graph) reads the previous
// tick's value. The host binds inputs to outputs by topic name, after checking that both sides
// carry the same message type (name and layout fingerprint, see tern/reflect.hpp).
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
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
  /// Host side (an isolated instance's proxy outputs): the type().size bytes at `bytes`, a
  /// message copied from the child process (reflect::bitwise_copyable types only), become the
  /// latest message, with sequence number `seq`.
  void publish_copy(const void* bytes, std::uint64_t seq) {
    std::memcpy(const_cast<void*>(data_), bytes, type().size);
    seq_ = seq;
  }
  /// Host side, between flights: nothing published yet (sequence 0, a default message), as
  /// after construction, so that a new flight's first consumers see what a fresh host's do.
  void clear() {
    clear_(const_cast<void*>(data_));
    seq_ = 0;
  }

 protected:
  OutputBase(const MsgType& type, const void* data, void (*clear)(void*)) : PortBase(type), data_(data), clear_(clear) {}
  const void* data_;
  std::uint64_t seq_ = 0;

 private:
  void (*clear_)(void*);  ///< assigns a default message to *data_
};

/// A plugin's output port carrying messages of type T.
template <class T>
class Output final : public OutputBase {
 public:
  Output() : OutputBase(msg_type_v<T>, &value_, [](void* v) { *static_cast<T*>(v) = T{}; }) {}
  /// Makes msg the latest message on the topic: O(sizeof(T)) copy, no allocation.
  void publish(const T& msg) {
    value_ = msg;
    ++seq_;
  }
  /// The message last published (a default T before the first publish).
  const T& last() const { return value_; }

 private:
  T value_{};
};

/// Whether an input must have a producer in the port graph.
enum class Need : std::uint8_t { required, optional };

class TERN_API InputBase : public PortBase {
 public:
  ~InputBase() override;
  bool connected() const { return src_ != nullptr; }
  /// A message has been published on the topic at least once.
  bool has_value() const { return src_ != nullptr && src_->sequence() > 0; }
  /// A message arrived since this plugin's previous step.
  bool updated() const { return src_ != nullptr && src_->sequence() != seen_; }
  Need need() const { return need_; }

  // host side
  void set_need(Need n) { need_ = n; }
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
  const OutputBase* src_ = nullptr;
  std::uint64_t seen_ = 0;
  Need need_ = Need::required;
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

 private:
  T fallback_{};
};

}  // namespace tern
