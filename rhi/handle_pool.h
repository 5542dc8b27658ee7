// Slot + generation storage behind the RHI's typed handles (after sokol_gfx's pools): a handle
// to a destroyed object is detected (get() returns null) instead of reaching freed memory.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "rhi/rhi.h"

namespace parity::rhi {

template <class HandleT, class T>
class HandlePool {
 public:
  static constexpr uint32_t kSlotBits = 20;
  static constexpr uint32_t kSlotMask = (1u << kSlotBits) - 1;

  HandleT add(T value) {
    uint32_t slot;
    if (!free_.empty()) {
      slot = free_.back();
      free_.pop_back();
    } else {
      slot = static_cast<uint32_t>(entries_.size());
      entries_.push_back({});
    }
    Entry& e = entries_[slot];
    e.generation = (e.generation + 1) & 0xFFF;
    if (e.generation == 0) e.generation = 1;
    e.value = std::move(value);
    return HandleT{(e.generation << kSlotBits) | (slot + 1)};
  }

  T* get(HandleT h) {
    Entry* e = entry(h);
    return e ? &*e->value : nullptr;
  }
  const T* get(HandleT h) const { return const_cast<HandlePool*>(this)->get(h); }

  // Removes and returns the object so the caller can release its native resources.
  std::optional<T> remove(HandleT h) {
    Entry* e = entry(h);
    if (!e) return std::nullopt;
    std::optional<T> out = std::move(e->value);
    e->value.reset();
    free_.push_back((h.id & kSlotMask) - 1);
    return out;
  }

  template <class F>
  void forEach(F&& f) {
    for (auto& e : entries_)
      if (e.value) f(*e.value);
  }

 private:
  struct Entry {
    uint32_t generation = 0;
    std::optional<T> value;
  };
  Entry* entry(HandleT h) {
    if (!h) return nullptr;
    uint32_t slot = (h.id & kSlotMask) - 1;
    if (slot >= entries_.size()) return nullptr;
    Entry& e = entries_[slot];
    if (!e.value || e.generation != (h.id >> kSlotBits)) return nullptr;
    return &e;
  }
  std::vector<Entry> entries_;
  std::vector<uint32_t> free_;
};

}  // namespace parity::rhi
