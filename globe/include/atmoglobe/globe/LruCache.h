#pragma once
// LruCache: a byte-budgeted least-recently-used cache (header-only).
//
// Thread-compatible, not thread-safe: the caller locks. Values are moved in; lookups return a
// pointer that stays valid until the next insert/erase/evict on the cache.
#include <cassert>
#include <cstddef>
#include <functional>
#include <list>
#include <unordered_map>
#include <utility>

namespace atmoglobe::globe {

template <class Key, class Value, class Hash = std::hash<Key>>
class LruCache {
 public:
  /// `budgetBytes`: the total of the `bytes` given to insert() the cache tries to stay within.
  explicit LruCache(std::size_t budgetBytes) : budgetBytes_(budgetBytes) {}

  /// The value for `key` (marked most recently used), or nullptr if absent.
  Value* find(const Key& key) {
    auto it = index_.find(key);
    if (it == index_.end()) return nullptr;
    entries_.splice(entries_.begin(), entries_, it->second);
    return &it->second->value;
  }

  /// True if `key` is present; does not change the LRU order.
  bool contains(const Key& key) const { return index_.count(key) != 0; }

  /// Inserts (or replaces) `key` as the most recently used entry accounting `bytes`, then evicts
  /// least-recently-used entries until the total is within budget. An entry larger than the
  /// whole budget is still kept, as the only entry.
  void insert(const Key& key, Value value, std::size_t bytes) {
    auto it = index_.find(key);
    if (it != index_.end()) {
      bytes_ -= it->second->bytes;
      it->second->value = std::move(value);
      it->second->bytes = bytes;
      entries_.splice(entries_.begin(), entries_, it->second);
    } else {
      entries_.push_front(Entry{key, std::move(value), bytes});
      index_.emplace(key, entries_.begin());
    }
    bytes_ += bytes;
    while (bytes_ > budgetBytes_ && entries_.size() > 1) evictOldest();
  }

  /// Removes `key` if present (not counted as an eviction). Returns whether it was present.
  bool erase(const Key& key) {
    auto it = index_.find(key);
    if (it == index_.end()) return false;
    bytes_ -= it->second->bytes;
    entries_.erase(it->second);
    index_.erase(it);
    return true;
  }

  /// Evicts least-recently-used entries while the cache is not empty and
  /// shouldEvict(const Key&, const Value&) returns true for the oldest one.
  template <class F>
  void evictWhile(F shouldEvict) {
    while (!entries_.empty() && shouldEvict(entries_.back().key, entries_.back().value)) evictOldest();
  }

  void clear() {
    entries_.clear();
    index_.clear();
    bytes_ = 0;
  }

  std::size_t bytes() const { return bytes_; }
  std::size_t size() const { return entries_.size(); }
  std::size_t budgetBytes() const { return budgetBytes_; }
  /// Entries removed to respect the budget or by evictWhile since construction.
  std::size_t evictions() const { return evictions_; }

 private:
  struct Entry {
    Key key;
    Value value;
    std::size_t bytes;
  };

  void evictOldest() {
    assert(!entries_.empty());
    Entry& e = entries_.back();
    bytes_ -= e.bytes;
    index_.erase(e.key);
    entries_.pop_back();
    ++evictions_;
  }

  std::size_t budgetBytes_;
  std::size_t bytes_ = 0;
  std::size_t evictions_ = 0;
  std::list<Entry> entries_;  // front = most recently used
  std::unordered_map<Key, typename std::list<Entry>::iterator, Hash> index_;
};

}  // namespace atmoglobe::globe
