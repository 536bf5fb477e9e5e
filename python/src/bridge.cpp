#include "bridge.hpp"

#include <algorithm>

#include "vehs/core/error.hpp"

namespace vehs::python {

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
  tools::Config c(std::move(j), where);
  c.check_keys(allowed);
  return c;
}

std::string json_text(const nlohmann::ordered_json& j) { return j.dump(); }

ProgressBridge::ProgressBridge(nb::object callable, bool cancel)
    : callable_(std::move(callable)), cancel_(cancel) {}

ProgressBridge::~ProgressBridge() {
  Py_XDECREF(type_);
  Py_XDECREF(value_);
  Py_XDECREF(traceback_);
}

ProgressCallback ProgressBridge::callback() {
  return [this](const ProgressEvent& e) { on_event(e); };
}

void ProgressBridge::on_event(const ProgressEvent& e) {
  if (stopped_.load()) {
    if (cancel_ && !e.finished) throw Error("interrupted");
    return;
  }
  {
    nb::gil_scoped_acquire gil;
    bool failed = PyErr_CheckSignals() != 0;  // runs the handlers on the main thread only
    if (!failed && callable_.is_valid() && !callable_.is_none()) {
      PyObject* r = PyObject_CallFunction(callable_.ptr(), "s#LLOd", e.task.data(),
                                          static_cast<Py_ssize_t>(e.task.size()), e.done, e.total,
                                          e.finished ? Py_True : Py_False, e.seconds);
      failed = r == nullptr;
      Py_XDECREF(r);
    }
    if (!failed) return;
    PyErr_Fetch(&type_, &value_, &traceback_);
    stopped_.store(true);
  }
  if (cancel_ && !e.finished) throw Error("interrupted");
}

void ProgressBridge::finish() {
  if (!stopped_.load() && PyErr_CheckSignals() != 0) throw nb::python_error();
  if (!stopped_.load() || type_ == nullptr) return;
  PyErr_Restore(type_, value_, traceback_);
  type_ = value_ = traceback_ = nullptr;
  throw nb::python_error();
}

}  // namespace vehs::python
