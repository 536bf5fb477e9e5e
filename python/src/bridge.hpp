#pragma once
// Glue between Python and the library: configs from keyword arguments (the executables' key
// tables, so that Python and the CLI take the same keys and give the same one-line errors),
// JSON in and out, and the progress callback that also watches for Ctrl-C.
#include <atomic>
#include <csignal>
#include <string>
#include <type_traits>
#include <vector>

#include <nanobind/nanobind.h>
#include <nlohmann/json.hpp>

#include "tools/config.hpp"
#include "vehs/core/progress.hpp"

namespace vehs::python {
namespace nb = nanobind;

/// The Config of the keyword arguments `options_json` (a JSON object as text), named `where` in
/// error messages ("vehs.identify: 'estimator' must be ..."). Keys must be in `schema` and not
/// in `excluded` (the file keys that the Python call takes as arguments instead).
tools::Config config_from_json(const std::string& options_json, const std::string& where,
                               const tools::ConfigSchema& schema, const std::vector<std::string>& excluded);

/// nlohmann JSON as text for Python's json.loads (one conversion at the boundary).
std::string json_text(const nlohmann::ordered_json& j);

/// Forwards the library's progress events to a Python callable (or none), with the GIL briefly
/// re-acquired, and watches for Ctrl-C. Python runs its signal handlers only on the main thread,
/// which may sit idle in an OpenMP barrier while other threads work, so during a call made from
/// the main thread SIGINT goes to a handler of our own that only sets a flag, which every event
/// sees on whatever thread it comes. Once Ctrl-C or an exception of the callable is seen, further
/// events are not forwarded and, with `cancel`, the next intermediate event throws
/// vehs::Error("interrupted"), which the simulator turns into a clean stop of every thread.
/// finish() restores the Python handler, hands it the signal, and raises what was caught.
class ProgressBridge {
 public:
  ProgressBridge(nb::object callable, bool cancel);
  ~ProgressBridge();
  ProgressBridge(const ProgressBridge&) = delete;
  ProgressBridge& operator=(const ProgressBridge&) = delete;

  /// The callback for the library's options (valid while this bridge lives).
  ProgressCallback callback();
  /// With the GIL held: restores the SIGINT handler and throws nb::python_error for a caught
  /// Ctrl-C (KeyboardInterrupt, or what the Python handler raises) or exception of the callable.
  void finish();
  bool stopped() const;

 private:
  void on_event(const ProgressEvent& e);
  void restore_handler();
  nb::object callable_;
  bool cancel_;
  bool handler_installed_ = false;
  struct sigaction previous_ {};
  std::atomic<bool> stopped_{false};
  PyObject* type_ = nullptr;
  PyObject* value_ = nullptr;
  PyObject* traceback_ = nullptr;
};

/// Runs `work(progress callback)` with the GIL released and progress bridged; rethrows a Ctrl-C
/// or an exception of the progress callable as the Python exception it was, else the library's
/// own exceptions.
template <class Work>
auto run_released(nb::object progress, bool cancel, Work&& work) {
  ProgressBridge bridge(std::move(progress), cancel);
  const ProgressCallback cb = bridge.callback();
  try {
    if constexpr (std::is_void_v<decltype(work(cb))>) {
      {
        nb::gil_scoped_release release;
        work(cb);
      }
      bridge.finish();
    } else {
      auto result = [&] {
        nb::gil_scoped_release release;
        return work(cb);
      }();
      bridge.finish();
      return result;
    }
  } catch (const nb::python_error&) {
    throw;
  } catch (const std::exception&) {
    bridge.finish();  // a Ctrl-C behind the library's "interrupted" surfaces as itself
    throw;
  }
}

}  // namespace vehs::python
