#include "solvers/pipeline/two_starts.h"

#include <condition_variable>
#include <deque>
#include <limits>
#include <mutex>
#include <thread>

namespace nrsfm {
namespace {

// The state both refinements and the calling thread share; every field is
// guarded by `mutex_`.
class Race {
 public:
  Race(bool concurrent, bool asks, bool stop)
      : concurrent_(concurrent), asks_(asks), user_stop_(stop) {}

  // Lane c's progress: record and queue the report for the calling thread.
  void Report(int c, const IterationReport& report) {
    std::lock_guard<std::mutex> lock(mutex_);
    Lane& lane = lanes_[c];
    lane.iteration = report.iteration;
    lane.cost = report.cost;
    lane.reports.push_back(report);
    lane.generation = ++generation_;
    changed_.notify_all();
  }

  // Lane c's stop_requested: after its iteration i, wait until the calling
  // thread has asked the caller's stop_requested since lane c reported i,
  // then for the other lane to reach i (or to end) — in turns when not
  // concurrent — then decide.
  bool ShouldStop(int c) {
    std::unique_lock<std::mutex> lock(mutex_);
    Lane& lane = lanes_[c];
    const Lane& other = lanes_[1 - c];
    const int i = lane.iteration;
    if (i < 0) return user_stop_;  // asked before the refinement began
    if (asks_) {
      changed_.wait(lock, [&] { return asked_ >= lane.generation; });
    }
    if (concurrent_) {
      changed_.wait(lock, [&] {
        return other.iteration >= i || other.ended || user_stop_;
      });
    } else {
      turn_ = 1 - c;
      changed_.notify_all();
      changed_.wait(lock,
                    [&] { return turn_ == c || other.ended || user_stop_; });
    }
    if (user_stop_) return true;
    // The other's end counts from the iteration after its last one, so the
    // decision does not depend on when its thread got to record it.
    const RaceOutcome& o = other.outcome;
    return other.ended && o.converged && o.usable && o.iterations < i &&
           i >= RaceIterations(o.iterations) && lane.cost >= o.final_cost;
  }

  // Lane c waits for its first turn (not concurrent: lane 0 begins).
  void WaitForFirstTurn(int c) {
    if (concurrent_) return;
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(
        lock, [&] { return turn_ == c || lanes_[1 - c].ended || user_stop_; });
  }

  void End(int c, const RaceOutcome& outcome) {
    std::lock_guard<std::mutex> lock(mutex_);
    lanes_[c].ended = true;
    lanes_[c].outcome = outcome;
    turn_ = 1 - c;
    changed_.notify_all();
  }

  // On the calling thread: forwards lane 0's reports, then lane 1's, to
  // `solver.progress`, asking `solver.stop_requested` after each — and once
  // after any report of the lane not yet forwarded, which waits for that
  // answer — until both lanes have ended.
  void Forward(const SolverOptions& solver) {
    for (int c = 0; c < 2; ++c) {
      std::unique_lock<std::mutex> lock(mutex_);
      while (true) {
        changed_.wait(lock, [&] {
          return !lanes_[c].reports.empty() || lanes_[c].ended ||
                 (asks_ && asked_ < generation_);
        });
        const int generation = generation_;
        std::deque<IterationReport> batch;
        batch.swap(lanes_[c].reports);
        const bool ended = lanes_[c].ended;
        lock.unlock();
        bool stop = false;
        for (const IterationReport& report : batch) {
          if (solver.progress) solver.progress(report);
          stop = stop || (asks_ && solver.stop_requested());
        }
        if (batch.empty() && asks_) stop = solver.stop_requested();
        lock.lock();
        user_stop_ = user_stop_ || stop;
        asked_ = generation;
        changed_.notify_all();
        if (ended && lanes_[c].reports.empty()) break;
      }
    }
  }

 private:
  struct Lane {
    int iteration = -1;  // the last iteration reported
    double cost = std::numeric_limits<double>::infinity();
    bool ended = false;
    RaceOutcome outcome;
    std::deque<IterationReport> reports;  // not yet forwarded
    int generation = 0;                   // generation_ at its last report
  };

  const bool concurrent_;
  std::mutex mutex_;
  std::condition_variable changed_;
  const bool asks_;  // the caller gave a stop_requested
  Lane lanes_[2];
  int turn_ = 0;
  int generation_ = 0;  // reports from either lane so far
  int asked_ = 0;       // generation_ when the caller was last asked
  bool user_stop_;
};

}  // namespace

void RunTwoRefinements(const SolverOptions& solver, bool concurrent,
                       const RaceRefinement& first,
                       const RaceRefinement& second) {
  // Asked once before the starts too, as Reconstruct() asks before a start.
  const bool asks = static_cast<bool>(solver.stop_requested);
  Race race(concurrent, asks, asks && solver.stop_requested());
  const RaceRefinement* refinements[2] = {&first, &second};
  std::thread lanes[2];
  for (int c = 0; c < 2; ++c) {
    lanes[c] = std::thread([&race, &solver, &refinements, c] {
      SolverOptions own = solver;
      own.progress = [&race, c](const IterationReport& report) {
        race.Report(c, report);
      };
      own.stop_requested = [&race, c] { return race.ShouldStop(c); };
      race.WaitForFirstTurn(c);
      race.End(c, (*refinements[c])(own));
    });
  }
  race.Forward(solver);
  for (std::thread& lane : lanes) lane.join();
}

}  // namespace nrsfm
