#include "column_memory.hpp"

#include <cstdlib>
#include <map>
#include <mutex>
#include <new>

namespace py = pybind11;

namespace geartopo::python {
namespace {

struct Block {
  void* data;
  std::size_t bytes;
};

/// Free blocks by size. Blocks are taken back with the GIL held (capsule destructors), but the lock costs nothing and
/// keeps the cache right whoever frees.
class BlockCache {
public:
  Block take(std::size_t bytes) {
    {
      const std::lock_guard lock(mutex_);
      // The smallest free block that fits, if it is not more than a quarter too big.
      if (auto it = free_.lower_bound(bytes); it != free_.end() && it->first <= bytes + bytes / 4) {
        Block b{it->second, it->first};
        free_.erase(it);
        cached_ -= b.bytes;
        return b;
      }
    }
    void* data = std::malloc(bytes);
    if (data == nullptr) throw std::bad_alloc();
    return {data, bytes};
  }

  void give_back(Block b) {
    {
      const std::lock_guard lock(mutex_);
      if (cached_ + b.bytes <= kCachedBytes) {
        free_.emplace(b.bytes, b.data);
        cached_ += b.bytes;
        return;
      }
    }
    std::free(b.data);
  }

private:
  std::mutex mutex_;
  std::multimap<std::size_t, void*> free_;
  std::size_t cached_ = 0;
};

/// Never destroyed: columns may be freed while the interpreter shuts down, after static destructors would have run.
BlockCache& cache() {
  static BlockCache* const c = new BlockCache;
  return *c;
}

} // namespace

py::array cached_array(const py::dtype& dtype, std::size_t n) {
  const auto item = static_cast<std::size_t>(dtype.itemsize());
  auto* block = new Block(cache().take(n * item > 0 ? n * item : 1));
  const py::capsule owner(block, [](void* p) {
    auto* b = static_cast<Block*>(p);
    cache().give_back(*b);
    delete b;
  });
  return py::array(dtype, {static_cast<py::ssize_t>(n)}, {static_cast<py::ssize_t>(item)}, block->data, owner);
}

} // namespace geartopo::python
