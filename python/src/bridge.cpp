#include "bridge.hpp"

#include <algorithm>

#include "vehs/core/error.hpp"

namespace vehs::python {

namespace {
// Set by the SIGINT handler installed during calls from the main thread (lock-free: async-signal-safe).
std::atomic<bool> g_sigint{false};
static_assert(std::atomic<bool>::is_always_lock_free);

extern "C" void on_sigint(int) { g_sigint.store(true); }

bool on_main_thread() {
  nb::module_ threading = nb::module_::import_("threading");
  return threading.attr("current_thread")().is(threading.attr("main_thread")());
}
}  // namespace

tools::Config config_from_json(const std::string& options_json, const std::string& where,
                               const tools::ConfigSchema& schema, const std::vector<std::string>& excluded) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(options_json);
  } catch (const nlohmann::json::exception& e) {
    throw Error(where + ": options are not JSON: " + e.what());
  }
  std::vector<std::string> allowed;
  for (const auto& k : schema.keys)
    if (std::find(excluded.begin(), excluded.end(), k.name) == excluded.end()) allowed.push_back(k.name);
  if (j.is_object() && j.contains("measurement")) {
    tools::Config(j, where).check_keys(allowed);  // 'measurement' itself must be one of the call's keys
    nlohmann::json given = j;
    tools::include_measurement_file(j, where, schema);
    for (const std::string& k : excluded)  // the call's own arguments (data, units, ...) are not taken from the file
      if (!given.contains(k)) j.erase(k);
  }
  tools::Config c(std::move(j), where);
  c.check_keys(allowed);
  return c;
}

std::string json_text(const nlohmann::ordered_json& j) { return j.dump(); }

ProgressBridge::ProgressBridge(nb::object callable, bool cancel)
    : callable_(std::move(callable)), cancel_(cancel) {
  if (!on_main_thread()) return;
  g_sigint.store(false);
  struct sigaction action {};
  action.sa_handler = on_sigint;
  sigemptyset(&action.sa_mask);
  handler_installed_ = sigaction(SIGINT, &action, &previous_) == 0;
}

ProgressBridge::~ProgressBridge() {
  restore_handler();
  Py_XDECREF(type_);
  Py_XDECREF(value_);
  Py_XDECREF(traceback_);
}

void ProgressBridge::restore_handler() {
  if (!handler_installed_) return;
  sigaction(SIGINT, &previous_, nullptr);
  handler_installed_ = false;
}

bool ProgressBridge::stopped() const { return stopped_.load() || (handler_installed_ && g_sigint.load()); }

ProgressCallback ProgressBridge::callback() {
  return [this](const ProgressEvent& e) { on_event(e); };
}

void ProgressBridge::on_event(const ProgressEvent& e) {
  if (!stopped() && callable_.is_valid() && !callable_.is_none()) {
    nb::gil_scoped_acquire gil;
    PyObject* task = PyUnicode_FromStringAndSize(e.task.data(), static_cast<Py_ssize_t>(e.task.size()));
    PyObject* r = task ? PyObject_CallFunction(callable_.ptr(), "OLLOd", task, e.done, e.total,
                                               e.finished ? Py_True : Py_False, e.seconds)
                       : nullptr;
    Py_XDECREF(task);
    if (r == nullptr) {
      PyErr_Fetch(&type_, &value_, &traceback_);
      stopped_.store(true);
    }
    Py_XDECREF(r);
  }
  if (cancel_ && !e.finished && stopped()) throw Error("interrupted");
}

void ProgressBridge::finish() {
  const bool interrupted = handler_installed_ && g_sigint.load();
  restore_handler();
  if (interrupted) {
    std::raise(SIGINT);  // to Python's own handler, which PyErr_CheckSignals then runs
    if (PyErr_CheckSignals() != 0) throw nb::python_error();
    // The handler did not raise (seen once under heavy load, cause not found; or a handler of the
    // user's that returns): the call was still stopped by Ctrl-C and has no result to return.
    PyErr_SetNone(PyExc_KeyboardInterrupt);
    throw nb::python_error();
  }
  if (type_ != nullptr) {
    PyErr_Restore(type_, value_, traceback_);
    type_ = value_ = traceback_ = nullptr;
    throw nb::python_error();
  }
}

}  // namespace vehs::python
