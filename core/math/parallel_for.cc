#include "core/math/parallel_for.h"

#include <unistd.h>

#include <condition_variable>
#include <mutex>
#include <thread>
#include <vector>

namespace nrsfm {
namespace internal {
namespace {

// True on a thread while it runs a piece of a pooled loop.
thread_local bool in_piece = false;

class Pool {
 public:
  // The pool of this process (a forked child gets a new one: the parent's
  // worker threads do not exist there). Never destroyed: its workers wait
  // until the process ends.
  static Pool& Get() {
    static std::mutex mutex;
    static Pool* pool = nullptr;
    static pid_t owner = 0;
    std::lock_guard<std::mutex> lock(mutex);
    if (pool == nullptr || owner != getpid()) {
      pool = new Pool();
      owner = getpid();
    }
    return *pool;
  }

  // Runs the loop on the pool; false (nothing run) when the pool is busy or
  // the caller is itself a piece.
  bool TryRun(int count, const std::function<void(int)>& piece) {
    if (in_piece || !busy_.try_lock()) return false;
    std::unique_lock<std::mutex> lock(mutex_);
    while (static_cast<int>(threads_.size()) < count - 1) {
      const int index = static_cast<int>(threads_.size()) + 1;
      threads_.emplace_back([this, index] { Work(index); });
    }
    piece_ = &piece;
    count_ = count;
    remaining_ = count - 1;
    ++generation_;
    lock.unlock();
    wake_.notify_all();
    in_piece = true;
    piece(0);
    in_piece = false;
    lock.lock();
    done_.wait(lock, [this] { return remaining_ == 0; });
    piece_ = nullptr;
    lock.unlock();
    busy_.unlock();
    return true;
  }

 private:
  Pool() = default;

  // Worker `index` runs piece `index` of every loop that has that many.
  void Work(int index) {
    long seen = 0;
    std::unique_lock<std::mutex> lock(mutex_);
    while (true) {
      wake_.wait(lock, [&] { return generation_ != seen; });
      seen = generation_;
      if (index >= count_) continue;
      const std::function<void(int)>* piece = piece_;
      lock.unlock();
      in_piece = true;
      (*piece)(index);
      in_piece = false;
      lock.lock();
      if (--remaining_ == 0) done_.notify_one();
    }
  }

  std::mutex busy_;   // held by the caller whose loop the pool runs
  std::mutex mutex_;  // guards what follows
  std::condition_variable wake_, done_;
  std::vector<std::thread> threads_;
  const std::function<void(int)>* piece_ = nullptr;
  int count_ = 0;
  int remaining_ = 0;
  long generation_ = 0;
};

}  // namespace

void RunPieces(int count, const std::function<void(int)>& piece) {
  if (count <= 1 || !Pool::Get().TryRun(count, piece)) {
    for (int i = 0; i < count; ++i) piece(i);
  }
}

}  // namespace internal
}  // namespace nrsfm
