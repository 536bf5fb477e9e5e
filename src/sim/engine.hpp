#pragma once
// Eigen's fixed-size lane arithmetic must be inlined into the hot loop; GCC's heuristics give up
// on the large batch function otherwise (measured: 30 % of the time in out-of-line Horner
// steps). This header is included first by the engine's translation units only.
#if defined(__GNUC__) && !defined(EIGEN_STRONG_INLINE)
#define EIGEN_STRONG_INLINE inline __attribute__((always_inline))
#endif
// The simulation engine (private to vehs_sim): batches of kLanes records integrated in lockstep
// (SIMD lanes), normals generated a block of steps at a time, batches spread over OpenMP threads.
// The fast path (the paper's polynomial family) is stepped by the SIMD kernels of the level in
// use (src/sim/simd/, vehs/sim/simd.hpp); the engine stores and accumulates what they return.
// The general path (ModelSystem: any term, every effect) is stepped here, with Eigen's lanes.
// The translation units run_<scheme>_fast.cpp and run_<scheme>_general.cpp instantiate
// run_fast<Stepper> and run_general<Stepper> (eight units compile in parallel).
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <limits>
#include <mutex>
#include <string>
#include <type_traits>
#include <vector>

#include <Eigen/Core>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "vehs/core/detail/progress_counter.hpp"
#include "vehs/core/statistics.hpp"
#include "vehs/core/dataset.hpp"
#include "vehs/sim/random.hpp"
#include "vehs/sim/simulate.hpp"
#include "vehs/sim/detail/model_system.hpp"
#include "vehs/sim/steppers.hpp"
#include "simd/kernel_table.hpp"

#if defined(__GNUC__)
#define VEHS_SIM_NOINLINE __attribute__((noinline))
#else
#define VEHS_SIM_NOINLINE
#endif

namespace vehs::sim::detail {

/// Records per SIMD batch (the kernels' 8 lanes: one AVX-512 register, two AVX2 or four SSE2
/// ones; results do not depend on the batching).
inline constexpr int kLanes = 8;
/// Moments accumulated for statistics, in this order.
inline constexpr int kMoments = 7;
inline const std::array<const char*, kMoments> kMomentNames = {"E[X]",  "E[Y]",  "E[X^2]", "E[Y^2]",
                                                               "E[XY]", "E[X^4]", "E[V^2]"};

struct RunContext {
  const CompiledModel* model = nullptr;
  const SimulationOptions* options = nullptr;
  CounterRng rng{1};
  double dt = 0.0, h = 0.0;
  int substeps = 1;
  std::size_t samples = 0;
  long long burn_intervals = 0;
  std::vector<double> x0, y0, eta0;   ///< per record (index 0 … records − 1)
  std::vector<const double*> drive;   ///< per record, empty without a drive
  Dataset* data = nullptr;            ///< x (and y) preallocated, or null
  // statistics
  bool stats = false;
  std::size_t stats_first = 0;        ///< first sample index used
  std::size_t batches = 1;
  std::vector<double> batch_sums;     ///< [(record · kMoments + moment) · batches + batch]
  bool histograms = false;
  std::vector<Histogram1D> hx, hy;    ///< per thread
  std::vector<Histogram2D> hxy;       ///< per thread
  vehs::detail::ProgressCounter* progress = nullptr;
  // failure
  std::atomic<bool> cancel{false};
  std::mutex failure_mutex;
  long long failed_record = -1;
  double failed_time = 0.0;
  std::string failure;                ///< message of the earliest failed record
  std::exception_ptr error;           ///< an exception thrown while stepping (e.g. by the progress
                                      ///< callback: "interrupted"), rethrown as it was
};

inline std::string format_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

VEHS_SIM_NOINLINE inline void report_failure(RunContext& ctx, long long record, double t, const std::string& what) {
  std::lock_guard<std::mutex> lock(ctx.failure_mutex);
  if (ctx.failed_record < 0 || record < ctx.failed_record) {
    ctx.failed_record = record;
    ctx.failed_time = t;
    ctx.failure = what;
  }
  ctx.cancel = true;
}

/// Standard normals of the Dynamics stream of L records, generated kBlock steps at a time:
/// step n uses normals [n·M, n·M + M) of each record's stream.
template <int L, int M>
struct NormalBlocks {
  static constexpr int kBlock = 64;
  static_assert((kBlock * M) % 2 == 0, "a block must hold whole Box–Muller pairs");
  const CounterRng* rng = nullptr;
  std::array<std::uint32_t, L> ids{};
  alignas(64) double buffer[kBlock * M * L];
  int cursor = kBlock;
  std::uint64_t step = 0;

  VEHS_SIM_NOINLINE void refill() {
    fill_normals<L>(*rng, ids, Purpose::Dynamics, step * M / 2, kBlock * M / 2, buffer);
    cursor = 0;
  }
  VEHS_SIM_INLINE const double* next() {
    if (cursor == kBlock) refill();
    const double* p = buffer + cursor * M * L;
    ++cursor;
    ++step;
    return p;
  }
};

/// The fast path's system as the engine sees it: PolynomialSystem's layout (state, lanes); the
/// SIMD kernels step PolynomialSystem itself (src/sim/simd/fast_kernel.hpp).
struct KernelSystem : PolynomialSystem<kLanes, 2> {
  using PolynomialSystem::PolynomialSystem;
};
static_assert(kLanes == FastBatch::kLanes, "the kernels run batches of kLanes records");

/// One batch of `active` records (padded to L lanes by copies of lane 0, which are integrated
/// but never written) integrated in lockstep from their initial state to the last sample.
template <class Stepper, class System>
class BatchRunner {
 public:
  static constexpr int L = System::lanes;
  static constexpr int M = Stepper::normals_per_source * System::noises;
  using State = typename System::State;
  using Lanes = typename System::Lanes;
  using Xi = Eigen::Map<const Eigen::Array<double, L, M>, Eigen::Aligned32>;

  BatchRunner(RunContext& ctx, std::size_t first, int active, int thread)
      : ctx_(ctx), o_(*ctx.options), sys_(*ctx.model), first_(first), active_(active), thread_(thread) {
    state_ = State::Zero();
    for (int l = 0; l < L; ++l) {
      const std::size_t r = first + static_cast<std::size_t>(l < active ? l : 0);
      rec_[static_cast<std::size_t>(l)] = r;
      normals_.ids[static_cast<std::size_t>(l)] = static_cast<std::uint32_t>(o_.first_record + r);
      state_(l, 0) = ctx.x0[r];
      state_(l, 1) = ctx.y0[r];
      if constexpr (System::has_colored) state_(l, System::colored_index) = ctx.eta0[r];
    }
    normals_.rng = &ctx.rng;
    if constexpr (kKernel) init_kernel();
    if (ctx.data)
      for (int l = 0; l < active; ++l) {
        const std::size_t off = rec_[static_cast<std::size_t>(l)] * ctx.samples;
        xs_[l] = ctx.data->x.data() + off;
        ys_[l] = ctx.data->y.empty() ? nullptr : ctx.data->y.data() + off;
      }
    for (auto& a : sums_) a = Lanes::Zero();
    n_used_ = ctx.samples > ctx.stats_first ? ctx.samples - ctx.stats_first : 0;
    next_flush_ = ctx.stats ? ctx.stats_first + batch_end(0) : 0;
  }

  void run() {
    // burn-in over [−burn_intervals·dt, 0), unrecorded
    for (long long k = 0; k < ctx_.burn_intervals; k += 1024) {
      const long long n = std::min<long long>(1024, ctx_.burn_intervals - k);
      burn(k - ctx_.burn_intervals, n);
      if (ctx_.cancel.load(std::memory_order_relaxed) || !healthy(state_)) break;
    }
    if (!healthy(state_)) return fail(0.0);
    record(state_, 0);
    constexpr std::size_t kChunk = 4096;
    for (std::size_t i = 1; i < ctx_.samples; i += kChunk) {
      const std::size_t end = std::min(ctx_.samples, i + kChunk);
      const std::size_t bad = samples(i, end);
      if (bad < end) return fail(static_cast<double>(bad) * ctx_.dt);
      if (ctx_.progress) ctx_.progress->advance(static_cast<long long>(active_) * static_cast<long long>(end - i));
      if (ctx_.cancel.load(std::memory_order_relaxed)) return;
    }
  }

 private:
  double bound() const { return o_.divergence_bound; }
  VEHS_SIM_INLINE bool healthy(const State& s) const { return (s.abs() <= bound()).all(); }
  std::size_t batch_end(std::size_t b) const { return (b + 1) * n_used_ / ctx_.batches; }

  static constexpr bool kKernel = std::is_same_v<System, KernelSystem>;
  static constexpr std::size_t kKernelChunk = 128;  ///< intervals per kernel call

  void burn(long long k0, long long n) {
    if constexpr (kKernel)
      burn_kernel(n);
    else
      burn_impl(k0, n);
  }
  std::size_t samples(std::size_t i0, std::size_t i1) {
    if constexpr (kKernel)
      return samples_kernel(i0, i1);
    else
      return samples_impl(i0, i1);
  }

  // ---- the fast path: the kernel of the SIMD level in use advances fast_ -------------------
  void init_kernel() {
    for (int l = 0; l < L; ++l) {
      fast_.x[l] = state_(l, 0);
      fast_.y[l] = state_(l, 1);
      fast_.records[l] = normals_.ids[static_cast<std::size_t>(l)];
    }
    fast_.key0 = ctx_.rng.key0();
    fast_.key1 = ctx_.rng.key1();
    run_.fast = &ctx_.model->fast;
    run_.h = ctx_.h;
    run_.substeps = ctx_.substeps;
    run_.bound = bound();
    advance_ = simd_kernels().advance[static_cast<int>(Stepper::scheme)];
  }
  void sync_state() {
    for (int l = 0; l < L; ++l) {
      state_(l, 0) = fast_.x[l];
      state_(l, 1) = fast_.y[l];
    }
  }
  /// n unrecorded intervals (stops early at a state out of the bound: run() reports it).
  VEHS_SIM_NOINLINE void burn_kernel(long long n) {
    advance_(run_, fast_, static_cast<std::size_t>(n), nullptr);
    sync_state();
  }
  /// As samples_impl, with the stepping done by the kernel kKernelChunk intervals at a time.
  VEHS_SIM_NOINLINE std::size_t samples_kernel(std::size_t i0, std::size_t i1) {
    for (std::size_t i = i0; i < i1;) {
      const std::size_t n = std::min(kKernelChunk, i1 - i);
      const std::size_t done = advance_(run_, fast_, n, out_);
      for (std::size_t j = 0; j < done; ++j, ++i) record(Eigen::Map<const State>(out_ + 2 * L * j), i);
      if (done < n) {
        sync_state();
        return i;
      }
    }
    sync_state();
    return i1;
  }

  /// n unrecorded intervals starting at interval index k0 (time k0·dt).
  VEHS_SIM_NOINLINE void burn_impl(long long k0, long long n) {
    State s = state_;
    const double h = ctx_.h, dt = ctx_.dt;
    for (long long k = 0; k < n; ++k) {
      const double t0 = static_cast<double>(k0 + k) * dt;
      for (int j = 0; j < ctx_.substeps; ++j) stepper_.step(sys_, s, t0 + j * h, h, Xi(normals_.next()));
    }
    state_ = s;
  }

  /// Integrates the intervals ending at samples i0 … i1 − 1 and records them. Returns i1, or
  /// the first sample at which the state left the divergence bound.
  VEHS_SIM_NOINLINE std::size_t samples_impl(std::size_t i0, std::size_t i1) {
    // everything the loop reads is copied into locals: the output stores (double*) would
    // otherwise force reloads of double members after every store
    State s = state_;
    const System& sys = sys_;
    int cursor = normals_.cursor;
    const double h = ctx_.h, dt = ctx_.dt, lim = bound();
    const int substeps = ctx_.substeps;
    const bool with_drive = !ctx_.drive.empty();
    const bool store = ctx_.data != nullptr, store_y = store && ys_[0] != nullptr;
    const bool full = active_ == L, sensor = store && o_.sensor_noise > 0.0;
    const bool stats = ctx_.stats;
    const std::size_t stats_first = ctx_.stats_first;
    double* xs[L];
    double* ys[L];
    for (int l = 0; l < L; ++l) xs[l] = xs_[l], ys[l] = ys_[l];
    for (std::size_t i = i0; i < i1; ++i) {
      if (with_drive) {
        Lanes u;
        for (int l = 0; l < L; ++l) u(l) = ctx_.drive[rec_[static_cast<std::size_t>(l)]][i - 1];
        sys_.set_drive(u);
      }
      const double t0 = static_cast<double>(i - 1) * dt;
      for (int j = 0; j < substeps; ++j) {
        if (cursor == NormalBlocks<L, M>::kBlock) {
          normals_.refill();
          cursor = 0;
        }
        stepper_.step(sys, s, t0 + j * h, h, Xi(normals_.buffer + cursor * M * L));
        ++cursor;
        ++normals_.step;
      }
      if (!(s.abs() <= lim).all()) {
        state_ = s;
        normals_.cursor = cursor;
        return i;
      }
      if (store) {
        if (sensor) {
          add_sensor_noise(s, i);
        } else if (full) {
#pragma GCC unroll 16
          for (int l = 0; l < L; ++l) xs[l][i] = s(l, 0);
          if (store_y) {
#pragma GCC unroll 16
            for (int l = 0; l < L; ++l) ys[l][i] = s(l, 1);
          }
        } else {
          for (int l = 0; l < active_; ++l) xs[l][i] = s(l, 0);
          if (store_y)
            for (int l = 0; l < active_; ++l) ys[l][i] = s(l, 1);
        }
      }
      if (stats && i >= stats_first) accumulate(s, i);
    }
    state_ = s;
    normals_.cursor = cursor;
    return i1;
  }

  VEHS_SIM_INLINE void record(const State& s, std::size_t i) {
    if (ctx_.data) {
      if (o_.sensor_noise > 0.0) {
        add_sensor_noise(s, i);
      } else {
        for (int l = 0; l < active_; ++l) xs_[l][i] = s(l, 0);
        if (ys_[0])
          for (int l = 0; l < active_; ++l) ys_[l][i] = s(l, 1);
      }
    }
    if (ctx_.stats && i >= ctx_.stats_first) accumulate(s, i);
  }

  VEHS_SIM_NOINLINE void add_sensor_noise(const State& s, std::size_t i) {
    if (i % 64 == 0 || !sensor_ready_) refill_sensor(i);
    for (int l = 0; l < active_; ++l) {
      xs_[l][i] = s(l, 0) + o_.sensor_noise * sensor_[(i % 64) * L + static_cast<std::size_t>(l)];
      if (ys_[0]) ys_[l][i] = s(l, 1);
    }
  }

  VEHS_SIM_NOINLINE void refill_sensor(std::size_t i) {
    const std::size_t block = i / 64 * 64;
    fill_normals<L>(ctx_.rng, normals_.ids, Purpose::SensorNoise, block / 2, 32, sensor_);
    sensor_ready_ = true;
  }

  VEHS_SIM_INLINE void accumulate(const State& s, std::size_t i) {
    const Lanes x = s.col(0), y = s.col(1);
    const Lanes x2 = x * x;
    sums_[0] += x;
    sums_[1] += y;
    sums_[2] += x2;
    sums_[3] += y * y;
    sums_[4] += x * y;
    sums_[5] += x2 * x2;
    if constexpr (System::has_electro) sums_[6] += s.col(System::electro_index).square();
    if (ctx_.histograms) add_histograms(s);
    if (i + 1 == next_flush_) flush();
  }

  VEHS_SIM_NOINLINE void add_histograms(const State& s) {
    const auto t = static_cast<std::size_t>(thread_);
    for (int l = 0; l < active_; ++l) {
      ctx_.hx[t].add(s(l, 0));
      ctx_.hy[t].add(s(l, 1));
      ctx_.hxy[t].add(s(l, 0), s(l, 1));
    }
  }

  VEHS_SIM_NOINLINE void flush() {
    for (int l = 0; l < active_; ++l)
      for (int m = 0; m < kMoments; ++m)
        ctx_.batch_sums[(rec_[static_cast<std::size_t>(l)] * kMoments + static_cast<std::size_t>(m)) *
                            ctx_.batches + batch_] = sums_[static_cast<std::size_t>(m)](l);
    for (auto& a : sums_) a = Lanes::Zero();
    ++batch_;
    // batches are non-empty because batches <= used samples
    next_flush_ = batch_ < ctx_.batches ? ctx_.stats_first + batch_end(batch_) : 0;
  }

  VEHS_SIM_NOINLINE void fail(double t) {
    for (int l = 0; l < active_; ++l) {
      bool ok = true;
      for (int c = 0; c < System::dim; ++c) ok = ok && std::abs(state_(l, c)) <= bound();
      if (!ok) {
        report_failure(ctx_, static_cast<long long>(o_.first_record + first_) + l, t,
                       std::isfinite(state_(l, 0)) && std::isfinite(state_(l, 1))
                           ? "left the divergence bound ±" + format_number(bound())
                           : "became non-finite");
        return;
      }
    }
    // only a padding lane (a copy of lane 0) can be left; it mirrors lane 0
    report_failure(ctx_, static_cast<long long>(o_.first_record + first_), t, "became non-finite");
  }

  RunContext& ctx_;
  const SimulationOptions& o_;
  const Stepper stepper_{};
  System sys_;
  std::size_t first_;
  int active_;
  int thread_;
  State state_;
  std::array<std::size_t, L> rec_{};
  NormalBlocks<L, M> normals_;
  FastBatch fast_;                     // the fast path's batch, stream position and normals
  FastRun run_;
  FastAdvance advance_ = nullptr;
  alignas(64) double out_[kKernelChunk * 2 * L];
  double* xs_[L] = {};
  double* ys_[L] = {};
  alignas(64) double sensor_[64 * L];
  bool sensor_ready_ = false;
  std::array<Lanes, kMoments> sums_;
  std::size_t n_used_ = 0, batch_ = 0, next_flush_ = 0;
};

template <class Stepper, class System>
void run_batch(RunContext& ctx, std::size_t first, int active, int thread) {
  BatchRunner<Stepper, System> runner(ctx, first, active, thread);
  runner.run();
}

template <class Stepper, class System>
void run_all_with(RunContext& ctx) {
  const std::size_t records = static_cast<std::size_t>(ctx.options->records);
  const long long batches = static_cast<long long>((records + kLanes - 1) / kLanes);
#pragma omp parallel for schedule(dynamic, 1)
  for (long long b = 0; b < batches; ++b) {
    if (ctx.cancel.load()) continue;
    int thread = 0;
#ifdef _OPENMP
    thread = omp_get_thread_num();
#endif
    const std::size_t first = static_cast<std::size_t>(b) * kLanes;
    try {
      run_batch<Stepper, System>(ctx, first, static_cast<int>(std::min<std::size_t>(kLanes, records - first)),
                                 thread);
    } catch (...) {
      std::lock_guard<std::mutex> lock(ctx.failure_mutex);
      if (!ctx.error) ctx.error = std::current_exception();
      ctx.cancel = true;
    }
  }
}

/// The paper's polynomial family: PolynomialSystem stepped by the SIMD kernels.
template <class Stepper>
void run_fast(RunContext& ctx) {
  run_all_with<Stepper, KernelSystem>(ctx);
}

/// ModelSystem with the hidden states the model's effects need.
template <class Stepper>
void run_general(RunContext& ctx) {
  const CompiledModel& m = *ctx.model;
  if (m.electro && m.colored)
    run_all_with<Stepper, ModelSystem<kLanes, true, true>>(ctx);
  else if (m.electro)
    run_all_with<Stepper, ModelSystem<kLanes, true, false>>(ctx);
  else if (m.colored)
    run_all_with<Stepper, ModelSystem<kLanes, false, true>>(ctx);
  else
    run_all_with<Stepper, ModelSystem<kLanes, false, false>>(ctx);
}

extern template void run_fast<EulerMaruyamaStepper>(RunContext&);
extern template void run_fast<Rk4EulerStepper>(RunContext&);
extern template void run_fast<BaoabStepper>(RunContext&);
extern template void run_fast<Taylor15Stepper>(RunContext&);
extern template void run_general<EulerMaruyamaStepper>(RunContext&);
extern template void run_general<Rk4EulerStepper>(RunContext&);
extern template void run_general<BaoabStepper>(RunContext&);
extern template void run_general<Taylor15Stepper>(RunContext&);

/// Runs every batch with the stepper, choosing the system the model needs.
template <class Stepper>
void run_all(RunContext& ctx) {
  if (ctx.model->fast.eligible)
    run_fast<Stepper>(ctx);
  else
    run_general<Stepper>(ctx);
}


}  // namespace vehs::sim::detail
