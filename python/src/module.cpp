// The extension module robophi._robophi (docs/python.md): errors, shared helpers,
// and the bindings of each part.
#include <cstdio>
#include <cstring>

#include "py_robophi.h"
#include "robophi/build/spec_error.h"
#include "robophi/joints.h"

namespace robophi::python {

py::array vec3View(const Vec3* data, std::size_t n, py::handle owner, bool writable) {
  const auto rows = static_cast<py::ssize_t>(n);
  py::array view(py::dtype::of<double>(), {rows, py::ssize_t{3}},
                 {static_cast<py::ssize_t>(sizeof(Vec3)), static_cast<py::ssize_t>(sizeof(double))},
                 reinterpret_cast<const double*>(data), owner);
  if (!writable)
    py::detail::array_proxy(view.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return view;
}

std::string pathText(const py::handle& path) {
  return py::str(py::module_::import("os").attr("fspath")(path));
}

Integrator integratorFromName(const std::string& name) {
  Integrator integrator{};
  if (!parseIntegrator(name, integrator))
    throw std::invalid_argument("integrator '" + name + "': expected taylor, symplectic or verlet");
  return integrator;
}

std::shared_ptr<const Scene> loadScene(const std::string& path) {
  return sceneOrThrow(loadSceneFile(path), path);
}

std::shared_ptr<const Scene> sceneOrThrow(SceneLoadResult result, const std::string& path,
                                          std::vector<std::string>* warnings) {
  if (warnings)
    for (const Diagnostic& d : result.warnings) warnings->push_back(d.format("warning"));
  if (result.ok()) return std::make_shared<const Scene>(std::move(*result.scene));
  // The CLI's lines (robophi validate, robophi run): each error, then the count.
  std::string message;
  for (const Diagnostic& d : result.errors) message += d.format("error") + "\n";
  message += path + ": " + std::to_string(result.errors.size()) +
             (result.errors.size() == 1 ? " error" : " errors") + "; nothing was run or written";
  throw SceneLoadError(message, std::move(result.errors));
}

std::size_t jointIndex(const Model& model, const py::handle& joint) {
  if (py::isinstance<py::str>(joint)) {
    const auto name = joint.cast<std::string>();
    if (const auto index = findJoint(model, name)) return *index;
    std::string known;
    for (const Joint& j : model.joints) known += (known.empty() ? "" : ", ") + j.name;
    throw py::key_error("no joint named '" + name +
                        "' (the model has: " + (known.empty() ? std::string("none") : known) + ")");
  }
  const auto index = joint.cast<std::int64_t>();
  if (index < 0 || static_cast<std::size_t>(index) >= model.joints.size())
    throw std::out_of_range("joint " + std::to_string(index) + " does not exist (there are " +
                            std::to_string(model.joints.size()) + ")");
  return static_cast<std::size_t>(index);
}

namespace {

// A Python exception class robophi.<name> with the given bases (new reference, kept).
py::object newError(py::module_& m, const char* name, py::tuple bases, const char* doc) {
  const std::string qualified = std::string("robophi.") + name;
  py::object type = py::reinterpret_steal<py::object>(
      PyErr_NewExceptionWithDoc(qualified.c_str(), doc, bases.ptr(), nullptr));
  if (!type) throw py::error_already_set();
  m.attr(name) = type;
  return type;
}

}  // namespace

void bindErrors(py::module_& m) {
  // Kept for the process's lifetime (handles, never released at exit): the
  // translator below uses them.
  static py::handle error, sceneError, specError, divergedError;
  error = newError(m, "Error", py::make_tuple(py::handle(PyExc_Exception)),
                   "Base of robophi's own exceptions.")
              .release();
  sceneError = newError(m, "SceneError", py::make_tuple(error, py::handle(PyExc_ValueError)),
                        "A scene file that does not load: the message has every error as "
                        "file:line:column: error: ... (at /pointer); .diagnostics lists them.")
                   .release();
  specError = newError(m, "SpecError", py::make_tuple(error, py::handle(PyExc_ValueError)),
                       "A builder spec or argument that cannot be built (.spec, .field).")
                  .release();
  divergedError =
      newError(m, "DivergedError", py::make_tuple(error, py::handle(PyExc_RuntimeError)),
               "A step made the state non-finite (NaN or infinite) or the adaptive "
               "step stalled.")
          .release();
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const SceneLoadError& e) {
      py::object instance = sceneError(e.what());
      py::list diagnostics;
      for (const Diagnostic& d : e.diagnostics) {
        py::dict item;
        item["file"] = d.file;
        item["line"] = d.line;
        item["column"] = d.column;
        item["pointer"] = d.pointer;
        item["message"] = d.message;
        diagnostics.append(item);
      }
      instance.attr("diagnostics") = diagnostics;
      PyErr_SetObject(sceneError.ptr(), instance.ptr());
    } catch (const build::SpecError& e) {
      py::object instance = specError(e.what());
      instance.attr("spec") = e.spec();
      instance.attr("field") = e.field();
      PyErr_SetObject(specError.ptr(), instance.ptr());
    } catch (const Diverged& e) {
      PyErr_SetString(divergedError.ptr(), e.what());
    }
  });
}

}  // namespace robophi::python

PYBIND11_MODULE(_robophi, m) {
  using namespace robophi::python;
  m.doc() = "robophi: particles tied by spring/damper connectors, for robots (docs/python.md)";
  bindErrors(m);
  bindModel(m);
  bindWorld(m);
  bindBuild(m);
  bindRun(m);
  bindUrdf(m);
  bindActuators(m);
  bindMultibody(m);
  bindSensors(m);
}
