// One plugin of each kind a Python class can be, from the same code: the kind is what the host
// sees in the handshake (a `controller` can be routed and replaced by the fallback, an
// `estimator` runs in `tern replay`). TERN_PYTHON_KIND is set per library (CMakeLists.txt).
#include "python_plugin.hpp"

#define TERN_PYTHON_NAME_(kind) "python_" #kind
#define TERN_PYTHON_NAME(kind) TERN_PYTHON_NAME_(kind)

TERN_PLUGIN(tern::python_plugin::PythonPlugin, TERN_PYTHON_NAME(TERN_PYTHON_KIND), tern::PluginKind::TERN_PYTHON_KIND,
            "a module written in Python: the class named by params.script and params.class (docs/python.md)");
