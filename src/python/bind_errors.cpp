// vpsim's exceptions as Python classes: vpsim.Error (base), InputError (with .file, .key,
// .reason, .line), ResourceError, GpuError (with .result). Every vpsim::Error crossing into
// Python becomes one of them; nothing reaches the interpreter as a crash.
#include "bind_common.h"
#include "vpsim/core/error.h"

namespace vpsim::python {

void bindErrors(py::module_& m) {
    static py::exception<Error> error(m, "Error");
    static py::exception<InputError> inputError(m, "InputError", error.ptr());
    static py::exception<ResourceError> resourceError(m, "ResourceError", error.ptr());
    static py::exception<GpuError> gpuError(m, "GpuError", error.ptr());
    error.doc() = "Base of every vpsim error; str(e) is the CLI's one-line message.";
    inputError.doc() =
        "Bad input: .file and .key name where (\"\" when not applicable), .reason what.";
    resourceError.doc() = "A request refused before allocating (memory, device limits, sizes).";
    gpuError.doc() = "A Vulkan call failed or no usable device exists; .result is the VkResult.";

    py::register_exception_translator([](std::exception_ptr p) {
        auto raise = [](const py::object& type, const Error& e, py::dict attributes) {
            py::object instance = type(e.what());
            for (auto item : attributes) instance.attr(item.first) = item.second;
            PyErr_SetObject(type.ptr(), instance.ptr());
        };
        try {
            if (p) std::rethrow_exception(p);
        } catch (const InputError& e) {
            py::dict a;
            a["file"] = e.file();
            a["key"] = e.key();
            a["reason"] = e.reason();
            a["line"] = e.line();
            raise(inputError, e, a);
        } catch (const ResourceError& e) {
            raise(resourceError, e, py::dict());
        } catch (const GpuError& e) {
            py::dict a;
            a["result"] = e.resultName();
            raise(gpuError, e, a);
        } catch (const Error& e) {
            raise(error, e, py::dict());
        }
    });
}

}  // namespace vpsim::python
