// The harness part of the Python module `lgvi` (built when the harness is: LGVI_BUILD_HARNESS):
// scenes (a TOML file, TOML text, or arguments), `simulate` of a scene with any registered
// method, the suites, `validate`, and the optimal control commands (indirect and direct,
// SLSQP and IPOPT). Each function goes through the same code as the CLI (load_scene, simulate,
// run_suite, compute_metrics/compare, run_ocp_command), so its validation, its files and its
// numbers are the CLI's; results come back as numpy arrays and dicts read from the files the
// run wrote (the CSVs' numbers are written in round-trip form, so nothing is lost).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <system_error>
#include <unistd.h>
#include <variant>
#include <vector>

#include "experiments/output/atomic_file.hpp"
#include "experiments/output/data_dir.hpp"
#include "experiments/suites/ensemble_statistics.hpp"
#include "experiments/suites/study.hpp"
#include "experiments/systems/systems.hpp"
#include "lgvi/systems/potential_body.hpp"
#include "experiments/output/csv_writer.hpp"
#include "experiments/methods/method.hpp"
#include "experiments/ocp/ocp_command.hpp"
#include "experiments/scene/ocp_scene.hpp"
#include "experiments/output/plot.hpp"
#include "experiments/scene/scene.hpp"
#include "experiments/methods/simulate.hpp"
#include "experiments/suites/suite.hpp"
#include "validation/validate.hpp"
#include "python_limits.hpp"

namespace py = pybind11;
namespace fs = std::filesystem;
namespace ex = lgvi::experiments;

namespace {

// --- files read back ------------------------------------------------------------------------------

/// A CSV written by the harness: `# key: value` metadata lines (leading, and for a stream a
/// trailer), one header row, numeric rows.
struct CsvTable {
  std::map<std::string, std::string> metadata;
  std::vector<std::string> columns;
  std::vector<double> values;  ///< row-major
  std::size_t rows = 0;
};

CsvTable read_csv(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw ex::OutputError(file.string() + ": cannot be read");
  CsvTable table;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    if (line.front() == '#') {
      const std::size_t colon = line.find(": ");
      if (colon != std::string::npos && colon > 2) table.metadata[line.substr(2, colon - 2)] = line.substr(colon + 2);
      continue;
    }
    std::vector<std::string> cells = ex::split_csv_row(line);
    if (table.columns.empty()) {
      table.columns = std::move(cells);
      continue;
    }
    if (cells.size() != table.columns.size()) {
      throw ex::OutputError(file.string() + ": a row has " + std::to_string(cells.size()) + " cells, the header " +
                            std::to_string(table.columns.size()));
    }
    for (const std::string& c : cells) {
      double x = std::numeric_limits<double>::quiet_NaN();  // an empty cell: no value
      if (!c.empty()) {
        const auto [end, ec] = std::from_chars(c.data(), c.data() + c.size(), x);
        if (ec != std::errc() || end != c.data() + c.size()) {
          // Not a number ("nan", "inf" are from_chars's own): the column is not numeric.
          throw ex::OutputError(file.string() + ": cell '" + c + "' is not a number");
        }
      }
      table.values.push_back(x);
    }
    ++table.rows;
  }
  return table;
}

/// The table as {column: (rows,) array} plus the paper's grouped variables where present:
/// "R" (rows, 3, 3) from R11..R33, "Omega" (rows, 3) from Omega1..3, likewise x, v and the
/// connected bodies' R1, R2, Omega1, Omega2.
py::dict columns_dict(const CsvTable& t) {
  const auto n = static_cast<py::ssize_t>(t.rows);
  const std::size_t m = t.columns.size();
  std::map<std::string, std::size_t> index;
  for (std::size_t j = 0; j < m; ++j) index[t.columns[j]] = j;
  py::dict columns;
  for (std::size_t j = 0; j < m; ++j) {
    py::array_t<double> a(n);
    for (py::ssize_t i = 0; i < n; ++i) a.mutable_at(i) = t.values[static_cast<std::size_t>(i) * m + j];
    columns[py::str(t.columns[j])] = a;
  }
  py::dict out;
  out["columns"] = columns;
  if (index.count("t") != 0) out["t"] = columns["t"];
  for (const auto& [prefix, key] : {std::pair{"R", "R"}, std::pair{"R1_", "R1"}, std::pair{"R2_", "R2"}}) {
    std::vector<std::size_t> js;
    for (int a = 1; a <= 3; ++a)
      for (int b = 1; b <= 3; ++b) {
        const auto it = index.find(prefix + std::to_string(a) + std::to_string(b));
        if (it != index.end()) js.push_back(it->second);
      }
    if (js.size() != 9) continue;
    py::array_t<double> R({n, py::ssize_t{3}, py::ssize_t{3}});
    for (py::ssize_t i = 0; i < n; ++i)
      for (int k = 0; k < 9; ++k) R.mutable_at(i, k / 3, k % 3) = t.values[static_cast<std::size_t>(i) * m + js[k]];
    out[key] = R;
  }
  for (const auto& [prefix, key] : {std::pair{"Omega", "Omega"}, std::pair{"x", "x"}, std::pair{"v", "v"},
                                    std::pair{"Omega1_", "Omega1"}, std::pair{"Omega2_", "Omega2"}}) {
    std::vector<std::size_t> js;
    for (int a = 1; a <= 3; ++a) {
      const auto it = index.find(prefix + std::to_string(a));
      if (it != index.end()) js.push_back(it->second);
    }
    if (js.size() != 3) continue;
    py::array_t<double> v({n, py::ssize_t{3}});
    for (py::ssize_t i = 0; i < n; ++i)
      for (int k = 0; k < 3; ++k) v.mutable_at(i, k) = t.values[static_cast<std::size_t>(i) * m + js[k]];
    out[key] = v;
  }
  py::dict metadata;
  for (const auto& [k, v] : t.metadata) metadata[py::str(k)] = v;
  out["metadata"] = metadata;
  return out;
}

py::object json_loads(const std::string& text) { return py::module_::import("json").attr("loads")(text); }

std::string read_text(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw ex::OutputError(file.string() + ": cannot be read");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Every line of a JSON-lines file as a dict.
py::list read_jsonl(const fs::path& file) {
  py::list rows;
  std::istringstream in(read_text(file));
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty()) rows.append(json_loads(line));
  }
  return rows;
}

py::object field_value(const ex::FieldValue& v) {
  return std::visit([](const auto& x) -> py::object { return py::cast(x); }, v);
}

py::dict fields_dict(const ex::Fields& fields) {
  py::dict d;
  for (const ex::Field& f : fields) d[py::str(f.key)] = field_value(f.value);
  return d;
}

/// A directory of its own under the system's temporary directory, removed on destruction (the
/// files of a run whose caller did not ask to keep them).
class ScratchDir {
 public:
  ScratchDir() {
    std::string pattern = (fs::temp_directory_path() / "lgvi-python-XXXXXX").string();
    if (mkdtemp(pattern.data()) == nullptr) throw ex::OutputError(pattern + ": cannot create a temporary directory");
    path_ = pattern;
  }
  ~ScratchDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

// --- scenes ---------------------------------------------------------------------------------------

/// A double as a TOML float that reads back as the same double: the shortest round-trip digits
/// (std::to_chars), ".0" added to an integral value; inf and nan as TOML spells them (the scene
/// parser then names the field: numbers must be finite).
std::string toml_float(double x) {
  char buf[64];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, x);
  std::string text(buf, end);
  if (text.find_first_of(".eni") == std::string::npos) text += ".0";  // "inf", "nan" hold 'n'
  return text;
}

/// A TOML basic string: quotes, backslashes and control characters escaped.
std::string toml_string(const std::string& s) {
  std::string out = "\"";
  for (const char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      case '\r': out += "\\r"; break;
      default:
        if (c < 0x20 || c == 0x7f) {
          char esc[8];
          std::snprintf(esc, sizeof esc, "\\u%04X", c);
          out += esc;
        } else {
          out += ch;
        }
    }
  }
  return out + "\"";
}

/// A Python str as UTF-8; a string Python cannot encode so (a lone surrogate, "\\ud800") is a
/// ValueError naming `path`, not pybind11's failed cast (RuntimeError).
std::string utf8_text(const py::handle& value, const std::string& path) {
  Py_ssize_t size = 0;
  const char* data = PyUnicode_AsUTF8AndSize(value.ptr(), &size);
  if (data == nullptr) {
    PyErr_Clear();
    throw py::value_error(path + ": not valid Unicode text (a lone surrogate cannot be written as UTF-8)");
  }
  return std::string(data, static_cast<std::size_t>(size));
}

/// A Python value as the text of a TOML value: bool, integer, float (Python's or numpy's), str, a
/// sequence (list, tuple, numpy array) as an array, a dict as an inline table. Anything else, an
/// integer outside TOML's 64 bits, text that is not Unicode and nesting deeper than a scene file
/// may hold (kMaxSceneNesting, which also ends a list that holds itself) are ValueErrors naming
/// `path` (the dotted key). Written here rather than by toml++'s formatter, whose inline-width
/// estimate casts log10 of a float below 1 to size_t (undefined behaviour, found by
/// UndefinedBehaviorSanitizer in the Python tests).
std::string toml_text(const py::handle& value, const std::string& path, int depth = 0) {
  const py::module_ numpy = py::module_::import("numpy");
  if (py::isinstance<py::bool_>(value) || py::isinstance(value, numpy.attr("bool_"))) {
    return value.cast<bool>() ? "true" : "false";
  }
  if (py::isinstance<py::int_>(value) || py::isinstance(value, numpy.attr("integer"))) {
    // numpy's integers through Python's (a uint64 past 2^63 included).
    const py::int_ integer(py::reinterpret_borrow<py::object>(value));
    int overflow = 0;
    const long long n = PyLong_AsLongLongAndOverflow(integer.ptr(), &overflow);
    if (overflow != 0) throw py::value_error(path + ": an integer outside TOML's 64-bit range (write it as a float)");
    if (n == -1 && PyErr_Occurred()) throw py::error_already_set();
    return std::to_string(n);
  }
  if (py::isinstance<py::float_>(value) || py::isinstance(value, numpy.attr("floating"))) {
    return toml_float(value.cast<double>());
  }
  if (py::isinstance<py::str>(value)) return toml_string(utf8_text(value, path));
  const bool is_dict = py::isinstance<py::dict>(value);
  const bool is_sequence =
      py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value) || py::isinstance<py::array>(value);
  if ((is_dict || is_sequence) && depth >= ex::kMaxSceneNesting) {
    throw py::value_error(path + ": nested more than " + std::to_string(ex::kMaxSceneNesting) +
                          " levels deep (a scene file holds at most that many)");
  }
  if (is_dict) {
    std::string text = "{";
    for (const auto& [k, v] : value.cast<py::dict>()) {
      if (!py::isinstance<py::str>(k)) {
        throw py::value_error(path + ": a key that is not a string (" +
                              py::str(k.get_type().attr("__name__")).cast<std::string>() + ")");
      }
      const std::string key = utf8_text(k, path + ".<key>");
      text += (text.size() > 1 ? ", " : " ") + toml_string(key) + " = " + toml_text(v, path + "." + key, depth + 1);
    }
    return text + (text.size() > 1 ? " }" : "}");
  }
  if (is_sequence) {
    const py::object items =
        py::isinstance<py::array>(value) ? value.attr("tolist")() : py::reinterpret_borrow<py::object>(value);
    std::string text = "[";
    for (const py::handle item : items) text += (text.size() > 1 ? ", " : "") + toml_text(item, path, depth + 1);
    return text + "]";
  }
  throw py::value_error(path + ": not a number, string, sequence or dict (got " +
                        py::str(value.get_type().attr("__name__")).cast<std::string>() + ")");
}

ex::SceneOverrides overrides_of(std::optional<double> h, std::optional<double> t_final,
                                std::optional<std::string> form, std::optional<std::int64_t> output_every) {
  ex::SceneOverrides o;
  o.h = h;
  o.t_final = t_final;
  if (form) o.form = lgvi::parse_lgvi_form(*form);
  o.output_every = output_every;
  return o;
}

fs::path scenes_dir_or_default(const std::optional<fs::path>& dir) { return dir ? *dir : ex::default_scenes_dir(); }

/// A scene from arguments: the same table a scene file holds (experiments/scene/scene.hpp), written as
/// TOML and validated by the same parser, so its errors name the same fields.
ex::Scene make_scene(const std::string& system, const py::dict& parameters, const py::dict& initial, double h,
                     double t_final, const std::string& form, std::int64_t output_every,
                     const std::optional<py::dict>& control, const std::string& name,
                     const std::optional<std::string>& description) {
  // The top-level keys first, then the [integration] table.
  std::ostringstream text;
  text << "system = " << toml_string(system) << "\n";
  if (description) text << "description = " << toml_string(*description) << "\n";
  text << "parameters = " << toml_text(parameters, "parameters") << "\n";
  if (!initial.empty()) text << "initial = " << toml_text(initial, "initial") << "\n";
  if (control) text << "control = " << toml_text(*control, "control") << "\n";
  text << "[integration]\nh = " << toml_float(h) << "\nt_final = " << toml_float(t_final)
       << "\nform = " << toml_string(form) << "\noutput_every = " << output_every << "\n";
  return ex::parse_scene(text.str(), fs::path(name + ".toml"));
}

// --- a potential from Python callables -----------------------------------------------------------

using Mat3 = lgvi::Mat3;
using Vec3 = lgvi::Vec3;

/// R as a (3, 3) array.
py::array_t<double> matrix_array(const Mat3& R) {
  py::array_t<double> a({py::ssize_t{3}, py::ssize_t{3}});
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) a.mutable_at(i, j) = R(i, j);
  return a;
}

/// The Python callables of a user potential (lgvi::UserPotential) and what they ran into: the
/// first failure (a callable that raised, a value of the wrong shape, a non-finite one), kept
/// until the run that met it has ended. After a failure the callables answer NaN without calling
/// Python, so every method stops at once. Held by shared_ptr: copies of the scene (made with the
/// GIL released) copy no Python reference; the last owner takes the GIL to release them.
struct CallbackRecord {
  py::object potential, moment, torque, force;
  std::string failure;  ///< "moment(R) returned array([1., 2.]) (expected 3 floats)"; empty: none
  py::object cause;     ///< the exception a callable raised, if any
  long long calls = 0;  ///< calls of either callable, over the record's life
  ~CallbackRecord() {
    py::gil_scoped_acquire gil;
    potential = py::object();
    moment = py::object();
    torque = py::object();
    force = py::object();
    cause = py::object();
  }
};

/// Calls `call`() (a callable of the record on its arguments) with the GIL taken (a run releases
/// it); `convert` gives the value or nullopt for a wrong type or shape. Any failure is recorded
/// and answered with NaN. `name`: "moment(R)", "torque(t, R, Omega)".
template <class Result, class Call, class Convert>
Result call_back(CallbackRecord& record, const char* name, const char* expected, Call call, Convert convert) {
  Result value = Result::Constant(std::numeric_limits<double>::quiet_NaN());
  py::gil_scoped_acquire gil;
  if (!record.failure.empty()) return value;
  ++record.calls;
  try {
    const py::object returned = call();
    const std::optional<Result> converted = convert(returned);
    if (!converted) {
      record.failure = std::string(name) + " returned " +
                       py::str(py::repr(returned)).cast<std::string>().substr(0, 200) + " (expected " + expected + ")";
    } else if (!converted->allFinite()) {
      record.failure = std::string(name) + " returned a non-finite value";
    } else {
      value = *converted;
    }
  } catch (py::error_already_set& e) {
    record.failure = std::string(name) + " raised " + py::str(e.type().attr("__name__")).cast<std::string>() +
                     ": " + py::str(e.value()).cast<std::string>();
    record.cause = e.value();
  }
  return value;
}

using Scalar1 = Eigen::Matrix<double, 1, 1>;
using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

/// A returned (3,) array-like, or nullopt.
std::optional<Vec3> vector_of(const py::object& v) {
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(v);
  if (py::isinstance<py::str>(v) || !a || a.ndim() != 1 || a.shape(0) != 3) return std::nullopt;
  return Vec3(a.at(0), a.at(1), a.at(2));
}

/// The float a potential returned (a Python or numpy real scalar: numpy's are float subclasses
/// or 0-d), or nullopt.
std::optional<Scalar1> scalar_of(const py::object& v) {
  const auto a = py::array_t<double, py::array::forcecast>::ensure(v);
  if (py::isinstance<py::str>(v) || py::isinstance<py::bytes>(v) || !a || a.ndim() != 0) return std::nullopt;
  return Scalar1::Constant(*a.data());
}

/// A (3,) array of v.
py::array_t<double> vector_array(const Vec3& v) {
  py::array_t<double> a(3);
  for (int i = 0; i < 3; ++i) a.mutable_at(i) = v(i);
  return a;
}

/// The user potential's U(R) (a std::function target that carries the record).
struct UserEnergy {
  std::shared_ptr<CallbackRecord> record;
  double operator()(const Mat3& R) const {
    return call_back<Scalar1>(*record, "potential(R)", "a float", [&] { return record->potential(matrix_array(R)); },
                              scalar_of)(0);
  }
};

/// The user potential's M(R).
struct UserMoment {
  std::shared_ptr<CallbackRecord> record;
  Vec3 operator()(const Mat3& R) const {
    return call_back<Vec3>(*record, "moment(R)", "3 floats", [&] { return record->moment(matrix_array(R)); },
                           vector_of);
  }
};

/// The user's torque u(t, R, Omega), a body-frame moment (the scene's feedback law).
struct UserTorque {
  std::shared_ptr<CallbackRecord> record;
  Vec3 operator()(double t, const Mat3& R, const Vec3& Omega) const {
    return call_back<Vec3>(*record, "torque(t, R, Omega)", "3 floats",
                           [&] { return record->torque(t, matrix_array(R), vector_array(Omega)); },
                           vector_of);
  }
};

/// A body with translation: U(R, x) (lgvi::UserPotentialSE3's energy).
struct UserEnergySE3 {
  std::shared_ptr<CallbackRecord> record;
  double operator()(const Mat3& R, const Vec3& x) const {
    return call_back<Scalar1>(*record, "potential(R, x)", "a float",
                              [&] { return record->potential(matrix_array(R), vector_array(x)); }, scalar_of)(0);
  }
};

/// A body with translation: its wrench, the force f(R, x) (inertial) and the moment M(R, x).
struct UserWrenchSE3 {
  std::shared_ptr<CallbackRecord> record;
  lgvi::Wrench operator()(const Mat3& R, const Vec3& x) const {
    lgvi::Wrench w;
    w.force = call_back<Vec3>(*record, "force(R, x)", "3 floats",
                              [&] { return record->force(matrix_array(R), vector_array(x)); }, vector_of);
    w.moment = call_back<Vec3>(*record, "moment(R, x)", "3 floats",
                               [&] { return record->moment(matrix_array(R), vector_array(x)); }, vector_of);
    return w;
  }
};

/// The record of a scene made by potential_scene, else null.
std::shared_ptr<CallbackRecord> user_record(const ex::Scene& scene) {
  if (const auto* body = std::get_if<ex::PotentialBodyModel>(&scene.model)) {
    const auto* user = std::get_if<lgvi::UserPotential>(&body->system.term);
    const auto* energy = user != nullptr ? user->energy.target<UserEnergy>() : nullptr;
    return energy != nullptr ? energy->record : nullptr;
  }
  if (const auto* body = std::get_if<ex::PotentialBodySE3Model>(&scene.model)) {
    const auto* user = std::get_if<lgvi::UserPotentialSE3>(&body->system.term);
    const auto* energy = user != nullptr ? user->energy.target<UserEnergySE3>() : nullptr;
    return energy != nullptr ? energy->record : nullptr;
  }
  return nullptr;
}

/// A scene whose potential is Python callables: without mass and force, of the system
/// potential-body, potential(R) -> float, moment(R) -> (3,) and, optionally, the torque
/// u(t, R, Omega) -> (3,); with mass and force, of the system potential-body-se3, potential(R, x),
/// moment(R, x) and force(R, x). Each callable is checked once at the initial state.
ex::Scene potential_scene(const py::object& inertia, const py::object& potential, const py::object& moment,
                          const py::dict& initial, double h, double t_final, const std::string& form,
                          std::int64_t output_every, const py::object& torque, const std::optional<py::dict>& control,
                          const std::string& name, const std::optional<std::string>& description,
                          const py::object& mass, const py::object& force) {
  const bool translates = !mass.is_none() || !force.is_none();
  const char* args = translates ? "(R, x)" : "(R)";
  if (!PyCallable_Check(potential.ptr())) throw py::type_error(std::string("potential: expected a callable U") + args + " -> float");
  if (!PyCallable_Check(moment.ptr())) throw py::type_error(std::string("moment: expected a callable M") + args + " -> (3,) array");
  if (translates) {
    if (mass.is_none()) throw py::value_error("mass: is required with force (a body with translation: mass [kg] and force(R, x))");
    if (force.is_none() || !PyCallable_Check(force.ptr())) {
      throw py::type_error("force: expected a callable f(R, x) -> (3,) array (inertial frame) with mass");
    }
    if (!torque.is_none()) {
      throw py::value_error(
          "torque: a feedback law u(t, R, Omega) is for the body without translation; with mass and force give "
          "control={'force': {...}, 'moment': {...}} (the dumbbell's time-dependent controls)");
    }
  }
  if (!torque.is_none() && !PyCallable_Check(torque.ptr())) {
    throw py::type_error("torque: expected a callable u(t, R, Omega) -> (3,) array, or None");
  }
  if (!torque.is_none() && control) throw py::value_error("torque: give torque or control, not both");
  // A placeholder (a zero dipole or zero gravity) gives the scene its inertia (and mass), initial
  // state, horizon and control, read and validated as a scene file's; the callables then replace it.
  py::dict parameters;
  parameters["inertia"] = inertia;
  py::dict start = initial;
  if (translates) {
    parameters["mass"] = mass;
    parameters["potential"] = "uniform-gravity";
    parameters["gravity"] = py::make_tuple(0.0, 0.0, 0.0);
    if (!start.contains("Omega") && !start.contains("omega_space")) start["Omega"] = py::make_tuple(0.0, 0.0, 0.0);
    if (!start.contains("x")) start["x"] = py::make_tuple(0.0, 0.0, 0.0);
    if (!start.contains("v")) start["v"] = py::make_tuple(0.0, 0.0, 0.0);
  } else {
    parameters["potential"] = "magnetic-dipole";
    parameters["dipole"] = py::make_tuple(0.0, 0.0, 0.0);
    parameters["field"] = py::make_tuple(0.0, 0.0, 0.0);
    if (start.empty()) start["Omega"] = py::make_tuple(0.0, 0.0, 0.0);  // R = I, at rest
  }
  ex::Scene scene = make_scene(translates ? "potential-body-se3" : "potential-body", parameters, start, h, t_final, form,
                               output_every, control, name,
                               description ? description : std::optional<std::string>("a potential defined in Python"));
  auto record = std::make_shared<CallbackRecord>();
  record->potential = potential;
  record->moment = moment;
  if (translates) {
    record->force = force;
    auto& body = std::get<ex::PotentialBodySE3Model>(scene.model);
    body.system = lgvi::PotentialBodySE3(body.system.mass, body.system.inertia.J,
                                         lgvi::UserPotentialSE3{UserEnergySE3{record}, UserWrenchSE3{record}});
    // The callables' answers at the initial state: a bad one is an error now, not mid-run.
    (void)body.system.potential(body.initial.R, body.initial.x);
    (void)body.system.forces(body.initial.R, body.initial.x);
  } else {
    auto& body = std::get<ex::PotentialBodyModel>(scene.model);
    body.system = lgvi::PotentialBody(body.system.inertia.J, lgvi::UserPotential{UserEnergy{record}, UserMoment{record}});
    if (!torque.is_none()) {
      record->torque = torque;
      ex::AttitudeFeedback law;
      law.law = UserTorque{record};
      body.feedback = law;
    }
    (void)body.system.potential(body.initial.R);
    (void)body.system.moment(body.initial.R);
    if (body.feedback) (void)body.feedback->moment(0.0, body.initial.R, body.initial.Omega);
  }
  if (!record->failure.empty()) {
    const std::string failure = record->failure;
    record->failure.clear();
    throw py::value_error(failure + " (at the initial state)");
  }
  scene.text = nullptr;  // no source text: the callables are not TOML
  return scene;
}

/// After a run of a user-potential scene: a failure of a callable becomes CallbackError naming the
/// callable, the reason and where the run stopped (its status); its __cause__ is the callable's
/// exception, if it raised.
void raise_callback_failure(const ex::Scene& scene, const std::string& where) {
  const std::shared_ptr<CallbackRecord> record = user_record(scene);
  if (!record || record->failure.empty()) return;
  const std::string message = record->failure + "; the run stopped: " + where;
  py::object error = py::module_::import("lgvi._lgvi").attr("CallbackError")(message);
  if (record->cause) PyException_SetCause(error.ptr(), record->cause.inc_ref().ptr());
  record->failure.clear();
  record->cause = py::object();
  PyErr_SetObject(reinterpret_cast<PyObject*>(Py_TYPE(error.ptr())), error.ptr());
  throw py::error_already_set();
}

// --- simulate -------------------------------------------------------------------------------------

py::dict simulate_scene(const ex::Scene& scene, const std::string& method_name, std::optional<std::string> model,
                        std::optional<double> rtol, std::optional<double> atol, std::optional<fs::path> csv) {
  ex::MethodOptions options;
  options.model = std::move(model);
  options.rtol = rtol;
  options.atol = atol;
  // The method's options validated as the CLI's (make_method: the tolerances' range,
  // baselines/tolerance.hpp); the rows read back into memory bounded (python_limits.hpp).
  const std::unique_ptr<ex::Method> method = ex::make_method(method_name, options);
  const ex::Horizon& hz = scene.horizon;
  lgvi::python::require_rows(
      std::floor(static_cast<double>(hz.steps) / static_cast<double>(hz.output_every)) + 2.0, "output_every",
      "the scene's steps / output_every (" + std::to_string(hz.steps) + " / " + std::to_string(hz.output_every) + ")");
  if (csv && *csv == "-") throw py::value_error("csv: a file to keep the rows in ('-', standard output, is the CLI's)");
  std::optional<ScratchDir> scratch;
  if (!csv) scratch.emplace();
  // Not named after the scene: a name need not make a file name (too long, a NUL, a slash).
  const fs::path file = csv ? *csv : scratch->path() / "rows.csv";
  ex::RunSummary summary;
  {
    py::gil_scoped_release release;
    summary = ex::simulate(scene, *method, {file, "python: lgvi.simulate", {}});
  }
  raise_callback_failure(scene, summary.stats.brief());
  py::dict out = columns_dict(read_csv(file));
  out["summary"] = fields_dict(summary.to_fields());
  out["csv"] = csv ? py::cast(*csv) : py::object(py::none());
  return out;
}

py::list method_list() {
  py::list out;
  for (const ex::MethodInfo& info : ex::method_registry()) {
    py::dict d;
    d["name"] = info.name;
    d["family"] = info.family == ex::MethodFamily::Lgvi           ? "lgvi"
                  : info.family == ex::MethodFamily::ComposedLgvi ? "composed-lgvi"
                  : info.family == ex::MethodFamily::OneStep      ? "one-step"
                                                                  : "baseline";
    d["order"] = info.order;
    d["stages"] = info.stages;
    d["fixed_step"] = info.fixed_step();
    d["uses_jacobian"] = info.uses_jacobian;
    py::list models;
    for (const auto m : info.models) models.append(std::string(lgvi::baselines::to_string(m)));
    d["models"] = models;
    d["takes_form"] = info.takes_form;
    d["legend"] = info.legend;
    py::dict traits;
    traits["symmetric"] = info.symmetric;
    traits["variational"] = info.variational;
    traits["symplectic"] = info.symplectic;
    traits["stays_on_group"] = info.stays_on_group;
    traits["preserves_momentum_map"] = info.preserves_momentum_map;
    traits["adaptive"] = info.adaptive();
    traits["must_complete_at_extremes"] = info.must_complete_at_extremes;
    traits["systems"] = info.systems;
    d["traits"] = traits;
    out.append(d);
  }
  return out;
}

// --- suites ---------------------------------------------------------------------------------------

py::list suite_cases(const std::string& name, bool quick, const std::optional<fs::path>& scenes_dir) {
  const ex::Suite suite = ex::make_suite(name, ex::SuiteParams{quick, scenes_dir_or_default(scenes_dir)});
  py::list out;
  for (const ex::SuiteCase& c : suite.cases) {
    py::dict d;
    d["id"] = c.id;
    d["group"] = c.group;
    d["expected"] = std::string(ex::to_string(c.expect));
    d["labels"] = fields_dict(c.labels);
    d["timed"] = c.job->timed();
    out.append(d);
  }
  return out;
}

/// The suite's run options from run_suite's and run_study's arguments, checked as the CLI checks
/// its options (--jobs, --shard, --format).
ex::SuiteOptions suite_options(const std::string& command, const fs::path& out, bool quick, unsigned jobs,
                               const std::optional<std::string>& shard, bool plots,
                               const std::optional<std::string>& formats, const std::optional<fs::path>& scenes_dir) {
  if (jobs < 1) throw py::value_error("jobs: must be >= 1");
  ex::SuiteOptions options;
  options.out_dir = out;
  options.scenes_dir = scenes_dir_or_default(scenes_dir);
  options.plots_dir = ex::default_plots_dir();
  options.gnuplot = ex::default_gnuplot();
  options.plots = plots;
  options.command_line = "python: " + command;
  if (shard) options.shard = ex::parse_shard(*shard);
  if (formats) options.formats = ex::figure_formats_named("formats", *formats);
  options.jobs = jobs;
  options.quick = quick;
  return options;
}

/// Runs `suite` into options.out_dir (created), returns summary.jsonl's rows.
py::list run_into(const ex::Suite& suite, const ex::SuiteOptions& options, bool progress) {
  const fs::path& out = options.out_dir;
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) throw ex::OutputError(out.string() + ": cannot create the output directory: " + ec.message());
  std::ostringstream log;
  {
    py::gil_scoped_release release;
    (void)ex::run_suite(suite, options, log);
  }
  if (progress) py::print(log.str(), py::arg("end") = "", py::arg("file") = py::module_::import("sys").attr("stderr"));
  return read_jsonl(out / "summary.jsonl");
}

/// Runs a suite into `out` (created) like `lgvi-testbed suite`, returns summary.jsonl's rows.
py::list run_suite(const std::string& name, const fs::path& out, bool quick, unsigned jobs,
                   const std::optional<std::string>& shard, bool plots, const std::optional<std::string>& formats,
                   const std::optional<fs::path>& scenes_dir, bool progress) {
  const ex::SuiteOptions options =
      suite_options("lgvi.run_suite('" + name + "')", out, quick, jobs, shard, plots, formats, scenes_dir);
  return run_into(ex::make_suite(name, ex::SuiteParams{quick, options.scenes_dir}), options, progress);
}

/// A study by path (containing '/' or ending in ".toml") or by the name of a shipped one.
fs::path resolve_study(const std::string& study) {
  const bool is_path = study.find('/') != std::string::npos || study.ends_with(".toml");
  if (is_path) return study;
  const fs::path file = ex::default_studies_dir() / (study + ".toml");
  std::error_code ec;
  if (fs::is_regular_file(file, ec)) return file;
  std::string known;
  for (fs::directory_iterator it(ex::default_studies_dir(), ec), end; !ec && it != end; it.increment(ec)) {
    if (it->path().extension() == ".toml") known += (known.empty() ? "" : ", ") + it->path().stem().string();
  }
  throw py::value_error("study: no shipped study '" + study + "' (shipped: " + known +
                        "; a path contains '/' or ends in .toml)");
}

/// Runs a study file into `out` like `lgvi-testbed study FILE --out OUT [--sample K]`, returns its rows.
py::list run_study(const std::string& study, const fs::path& out, bool quick, unsigned jobs,
                   const std::optional<std::string>& shard, bool plots, const std::optional<std::string>& formats,
                   const std::optional<fs::path>& scenes_dir, bool progress, std::optional<std::int64_t> sample) {
  const ex::SuiteOptions options =
      suite_options("lgvi.run_study('" + study + "')", out, quick, jobs, shard, plots, formats, scenes_dir);
  if (sample && *sample < 0) throw py::value_error("sample: must be >= 0 (got " + std::to_string(*sample) + ")");
  std::optional<std::size_t> k;
  if (sample) k = static_cast<std::size_t>(*sample);
  return run_into(ex::load_study(resolve_study(study), ex::SuiteParams{quick, options.scenes_dir, k}), options,
                  progress);
}

/// The statistics of the ensemble study run into `out` (NAME-statistics.csv's rows, computed
/// from OUT/summary.csv), as columns: text columns lists of str, the others lists of float (NaN
/// where there is no value) or int.
py::dict study_statistics(const fs::path& out) {
  const std::vector<ex::EnsembleStatistic> stats = ex::ensemble_statistics(ex::read_summary_csv(out / "summary.csv"));
  py::dict d;
  const auto text = [&](const char* key, auto member) {
    py::list l;
    for (const ex::EnsembleStatistic& s : stats) l.append(s.*member);
    d[key] = l;
  };
  text("group", &ex::EnsembleStatistic::group);
  text("label", &ex::EnsembleStatistic::label);
  text("method", &ex::EnsembleStatistic::method);
  text("model", &ex::EnsembleStatistic::model);
  text("h", &ex::EnsembleStatistic::h);
  text("rtol", &ex::EnsembleStatistic::rtol);
  text("metric", &ex::EnsembleStatistic::metric);
  text("samples", &ex::EnsembleStatistic::samples);
  text("completed", &ex::EnsembleStatistic::completed);
  text("count", &ex::EnsembleStatistic::count);
  text("median", &ex::EnsembleStatistic::median);
  text("q05", &ex::EnsembleStatistic::q05);
  text("q25", &ex::EnsembleStatistic::q25);
  text("q75", &ex::EnsembleStatistic::q75);
  text("q95", &ex::EnsembleStatistic::q95);
  text("max", &ex::EnsembleStatistic::max);
  text("failures", &ex::EnsembleStatistic::failures);
  text("failing_samples", &ex::EnsembleStatistic::failing_samples);
  return d;
}

// --- validate -------------------------------------------------------------------------------------

py::object optional_number(const std::optional<double>& x) { return x ? py::cast(*x) : py::object(py::none()); }

py::dict validate(bool quick, const std::vector<std::string>& only, const std::optional<fs::path>& accepted,
                  const std::optional<fs::path>& scenes_dir) {
  ex::ValidateOptions options;
  options.quick = quick;
  options.only = only;
  options.scenes_dir = scenes_dir_or_default(scenes_dir);
  const fs::path file = accepted ? *accepted : ex::default_accepted_file(quick);
  const ex::AcceptedFile before = ex::read_accepted(file);
  const std::string form = quick ? "quick" : "full";
  if (!before.form.empty() && before.form != form) {
    throw lgvi::InvalidInput(file.string(), "holds the " + before.form + " form's values; this run is the " + form +
                                                " form (quick=" + (quick ? "True" : "False") + ")");
  }
  std::ostringstream log;
  ex::ValidateReport report;
  {
    py::gil_scoped_release release;
    const std::vector<ex::Metric> metrics = ex::compute_metrics(options, log);
    report = ex::compare(metrics, before, only);
  }
  report.form = form;
  report.version = ex::git_describe();
  py::list rows;
  for (const ex::MetricComparison& r : report.rows) {
    py::dict d;
    d["name"] = r.name;
    d["kind"] = std::string(ex::to_string(r.kind));
    d["paper"] = optional_number(r.paper);
    d["accepted"] = optional_number(r.accepted);
    d["now"] = optional_number(r.now);
    d["verdict"] = std::string(ex::to_string(r.verdict));
    d["seconds"] = r.seconds;
    d["detail"] = r.detail;
    rows.append(d);
  }
  py::dict counts;
  for (const ex::Verdict v : {ex::Verdict::Pass, ex::Verdict::Regressed, ex::Verdict::Improved, ex::Verdict::Changed,
                              ex::Verdict::New, ex::Verdict::Missing}) {
    counts[ex::to_string(v)] = report.count(v);
  }
  std::ostringstream table;
  ex::print_report(report, table);
  py::dict out;
  out["form"] = form;
  out["accepted_file"] = file;
  out["accepted_at"] = report.accepted_at;
  out["version"] = report.version;
  out["rows"] = rows;
  out["counts"] = counts;
  out["regressed"] = report.failed();
  out["table"] = table.str();
  return out;
}

// --- optimal control ------------------------------------------------------------------------------

/// A keyword argument as T: TypeError naming `key` for a value of another type, ValueError for an
/// integer outside 64 bits (not pybind11's failed cast, a RuntimeError).
template <class T>
T option_value(const py::handle& value, const std::string& key) {
  try {
    return value.cast<T>();
  } catch (const py::cast_error&) {
    if constexpr (std::is_same_v<T, long long>) {
      if (PyLong_Check(value.ptr())) throw py::value_error(key + ": an integer outside the 64-bit range");
    }
    if constexpr (std::is_same_v<T, std::string> || std::is_same_v<T, fs::path>) {
      if (PyUnicode_Check(value.ptr())) (void)utf8_text(value, key);  // the surrogate's ValueError
    }
    const char* expected = std::is_same_v<T, std::string> ? "str"
                           : std::is_same_v<T, double>    ? "float"
                           : std::is_same_v<T, long long> ? "int"
                           : std::is_same_v<T, bool>      ? "bool"
                           : std::is_same_v<T, fs::path>  ? "a path (str or os.PathLike)"
                                                          : "a sequence of floats";
    throw py::type_error(key + ": expected " + expected + ", got " +
                         py::str(value.get_type().attr("__name__")).cast<std::string>());
  }
}

/// W as given to solve_ocp: a number per control (the diagonal) or a square matrix, as the flat
/// list of `ocp --weight` (row by row); its size and definiteness are the command's checks.
std::vector<double> weight_values(const py::handle& value) {
  // ensure: an empty handle (the error cleared) when value is no array of numbers.
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
  if (!a || a.ndim() > 2 || (a.ndim() == 2 && a.shape(0) != a.shape(1)) || a.ndim() == 0) {
    throw py::value_error("W: expected the diagonal (a sequence of floats) or a square matrix, got " +
                          py::str(py::repr(value)).cast<std::string>());
  }
  return {a.data(), a.data() + a.size()};
}

/// `lgvi-testbed ocp SYSTEM` with the given options; ValueError for bad input (exit status 1).
py::dict solve_ocp(const std::variant<std::string, ex::Scene>& problem, const py::kwargs& kwargs) {
  ex::OcpCommand cmd;
  // The scene `ocp SYSTEM` runs (a paper example's name, a scene name or a path, or a Scene made
  // in memory) names the files.
  std::string label;
  if (const auto* scene = std::get_if<ex::Scene>(&problem)) {
    if (!scene->text) throw py::value_error("scene: has no source text (make it by load_scene, parse_scene or make_scene)");
    cmd.scene = std::make_shared<const ex::Scene>(*scene);
    cmd.system = scene->name;
    label = ex::ocp_label(*scene);
  } else {
    cmd.system = std::get<std::string>(problem);
    try {
      label = ex::ocp_label(ex::load_scene(ex::resolve_ocp_scene(cmd.system, ex::default_scenes_dir())));
    } catch (const std::exception& e) {
      throw py::value_error(e.what());
    }
  }
  const std::string& system = cmd.system;
  std::optional<fs::path> keep;
  for (const auto& [key_handle, value] : kwargs) {
    const std::string key = py::str(key_handle);
    // Numbers as the CLI reads them (integers as 64-bit: a value out of its range is then the
    // range's ValueError, not a failed cast); run_ocp_command checks each against its range.
    if (key == "form") cmd.form = option_value<std::string>(value, key);
    else if (key == "h") cmd.h = option_value<double>(value, key);
    else if (key == "steps") cmd.steps = option_value<long long>(value, key);
    else if (key == "decomposition") cmd.no_decomposition = !option_value<bool>(value, key);
    else if (key == "merit") cmd.merit = option_value<std::string>(value, key);
    else if (key == "globalization") cmd.globalization = option_value<std::string>(value, key);
    else if (key == "lm_damping") cmd.lm_damping = option_value<double>(value, key);
    else if (key == "nonmonotone_memory") cmd.nonmonotone_memory = option_value<long long>(value, key);
    else if (key == "guess") cmd.guess = option_value<std::vector<double>>(value, key);
    else if (key == "W") cmd.weight = weight_values(value);
    else if (key == "max_iterations") cmd.max_iterations = option_value<long long>(value, key);
    else if (key == "t_final") cmd.t_final = option_value<double>(value, key);
    else if (key == "sphere_radius") cmd.sphere_radius = option_value<double>(value, key);
    else if (key == "knots") cmd.knots = option_value<long long>(value, key);
    else if (key == "spline") cmd.spline = option_value<std::string>(value, key);
    else if (key == "gradients") cmd.gradients = option_value<std::string>(value, key);
    else if (key == "tolerance") cmd.tolerance = option_value<double>(value, key);
    else if (key == "starts") cmd.starts = option_value<long long>(value, key);
    else if (key == "seed") cmd.seed = option_value<long long>(value, key);
    else if (key == "first_start") cmd.first_start = option_value<long long>(value, key);
    else if (key == "solver") cmd.solver = option_value<std::string>(value, key);
    else if (key == "hessian") cmd.hessian = option_value<std::string>(value, key);
    else if (key == "state_guess") cmd.state_guess = option_value<std::string>(value, key);
    else if (key == "shooting_interval") cmd.shooting_interval = option_value<long long>(value, key);
    else if (key == "intervals") cmd.intervals = option_value<long long>(value, key);
    else if (key == "out") keep = option_value<fs::path>(value, key);
    else throw py::value_error(key + ": not an option of solve_ocp (see its docstring)");
  }
  std::optional<ScratchDir> scratch;
  if (!keep) scratch.emplace();
  cmd.out = (keep ? *keep : scratch->path()).string();
  std::ostringstream out, err;
  int status = 0;
  try {
    py::gil_scoped_release release;
    status = ex::run_ocp_command(cmd, "python: lgvi.solve_ocp('" + system + "')", out, err);
  } catch (const lgvi::InvalidInput& e) {
    // The CLI's check, the argument named as Python's: "--max-iterations" is max_iterations.
    std::string field = e.field();
    if (field.rfind("--", 0) != 0) throw;
    const std::string what = e.what();
    const std::string reason = what.substr(std::min(what.size(), field.size() + 2));
    field.erase(0, 2);
    for (char& c : field) c = c == '-' ? '_' : c;
    if (field == "no_decomposition") field = "decomposition";
    if (field == "weight") field = "W";
    throw py::value_error(field + ": " + reason);
  }
  if (status == 1) {
    std::string message = err.str();
    while (!message.empty() && message.back() == '\n') message.pop_back();
    throw py::value_error(message);
  }
  const fs::path dir = cmd.out;
  ex::verify_ocp_run(dir, label);
  py::dict result;
  result["summary"] = json_loads(read_text(ex::ocp_output_file(dir, label, "summary.json")));
  const fs::path trajectory = ex::ocp_output_file(dir, label, "trajectory.csv");
  if (fs::exists(trajectory)) result["trajectory"] = columns_dict(read_csv(trajectory));
  result["history"] = columns_dict(read_csv(ex::ocp_output_file(dir, label, "history.csv")));
  const fs::path knots = ex::ocp_output_file(dir, label, "knots.csv");
  if (fs::exists(knots)) result["knots"] = columns_dict(read_csv(knots));
  result["converged"] = status == 0;
  result["out"] = keep ? py::cast(*keep) : py::object(py::none());
  return result;
}

}  // namespace

void bind_harness(py::module_& m) {
  // The project's version (CMake's PROJECT_VERSION), as every summary and CSV records it.
  m.attr("__version__") = ex::version();
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const ex::SceneError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const ex::OutputError& e) {
      PyErr_SetString(PyExc_OSError, e.what());
    }
  });

  py::class_<ex::Scene>(m, "Scene",
                        "A validated scene: system, parameters, initial state, horizon (experiments/scene/scene.hpp). "
                        "Made by load_scene, parse_scene or make_scene.")
      .def_readonly("name", &ex::Scene::name)
      .def_property_readonly("file", [](const ex::Scene& s) { return s.file; })
      .def_readonly("description", &ex::Scene::description)
      .def_property_readonly("system", [](const ex::Scene& s) { return std::string(s.system()); })
      .def_property_readonly("h", [](const ex::Scene& s) { return s.horizon.h; })
      .def_property_readonly("t_final", [](const ex::Scene& s) { return s.horizon.t_final; })
      .def_property_readonly("steps", [](const ex::Scene& s) { return s.horizon.steps; })
      .def_property_readonly("output_every", [](const ex::Scene& s) { return s.horizon.output_every; })
      .def_property_readonly("form", [](const ex::Scene& s) { return std::string(lgvi::to_string(s.form)); })
      .def("__repr__", [](const ex::Scene& s) {
        return "<lgvi.Scene '" + s.name + "': " + s.system() + ", h = " + ex::shortest(s.horizon.h) +
               ", t_final = " + ex::shortest(s.horizon.t_final) + ">";
      });

  m.def("scene_names", [](const std::optional<fs::path>& dir) { return ex::scene_names(scenes_dir_or_default(dir)); },
        py::arg("scenes_dir") = py::none(), "Names of the scenes in scenes_dir (default: the shipped scenes).");
  m.def("load_scene",
        [](const std::string& scene, const std::optional<fs::path>& dir, std::optional<double> h,
           std::optional<double> t_final, std::optional<std::string> form, std::optional<std::int64_t> every) {
          return ex::load_scene(ex::resolve_scene(scene, scenes_dir_or_default(dir)),
                                overrides_of(h, t_final, std::move(form), every));
        },
        py::arg("scene"), py::arg("scenes_dir") = py::none(), py::arg("h") = py::none(),
        py::arg("t_final") = py::none(), py::arg("form") = py::none(), py::arg("output_every") = py::none(),
        "A scene by name (in scenes_dir, default the shipped scenes) or by path (containing '/' or ending in "
        "'.toml'); h, t_final, form, output_every replace the file's [integration] values. ValueError names "
        "the file, field and reason.");
  m.def("parse_scene",
        [](const std::string& text, const std::string& name, std::optional<double> h, std::optional<double> t_final,
           std::optional<std::string> form, std::optional<std::int64_t> every) {
          return ex::parse_scene(text, fs::path(name + ".toml"), overrides_of(h, t_final, std::move(form), every));
        },
        py::arg("toml"), py::arg("name") = "scene", py::arg("h") = py::none(), py::arg("t_final") = py::none(),
        py::arg("form") = py::none(), py::arg("output_every") = py::none(),
        "A scene from TOML text in the scene file format (experiments/scene/scene.hpp).");
  m.def("make_scene", &make_scene, py::arg("system"), py::arg("parameters"), py::arg("initial") = py::dict(),
        py::kw_only(), py::arg("h"), py::arg("t_final"), py::arg("form") = "symmetric", py::arg("output_every") = 1,
        py::arg("control") = py::none(), py::arg("name") = "scene", py::arg("description") = py::none(),
        "A scene from arguments: parameters, initial and control are the scene file's tables as dicts "
        "(numbers, lists or numpy arrays), e.g. make_scene('free-body', {'inertia': [1, 2, 3]}, "
        "{'Omega': [0.1, 1, 0.1]}, h=0.01, t_final=10). Validated like a scene file.");

  // A failure of a user potential's callable (potential_scene), raised after the run it stopped.
  m.attr("CallbackError") = py::reinterpret_steal<py::object>(PyErr_NewExceptionWithDoc(
      "lgvi.CallbackError",
      "A callable of a user potential (potential_scene) raised, returned the wrong shape or a non-finite "
      "value during a run: the message names the callable, the reason and where the run stopped; __cause__ "
      "is the callable's own exception.",
      PyExc_RuntimeError, nullptr));
  m.def("potential_scene", &potential_scene, py::arg("inertia"), py::arg("potential"), py::arg("moment"),
        py::arg("initial") = py::dict(), py::kw_only(), py::arg("h"), py::arg("t_final"), py::arg("form") = "symmetric",
        py::arg("output_every") = 1, py::arg("torque") = py::none(), py::arg("control") = py::none(),
        py::arg("name") = "user-potential", py::arg("description") = py::none(), py::arg("mass") = py::none(),
        py::arg("force") = py::none(),
        "A scene of a rigid body in a potential defined in Python: inertia (3,) or (3, 3) [kg m^2]; "
        "potential(R) -> float, U [J]; moment(R) -> (3,), M(R) with hat(M) = dU/dR^T R - R^T dU/dR (eq. 13: "
        "minus the left-trivialized derivative, d/de U(R exp(hat(e))) = -M at e = 0); initial (default: R = I at "
        "rest), control and the horizon as make_scene's ('potential-body' system); torque(t, R, Omega) -> (3,), an "
        "optional body-frame feedback moment. With mass [kg] and force, a body that also translates "
        "('potential-body-se3' system): potential(R, x), moment(R, x) and force(R, x) -> (3,), f = -dU/dx "
        "(inertial frame); initial adds x and v (default 0); control takes the sub-tables force and moment. "
        "simulate(scene, method) runs it with every method that takes its system. A callable that raises or "
        "returns a wrong shape or a non-finite value stops the run, and simulate raises CallbackError naming it "
        "and the step; each is checked once at the initial state here (ValueError).");
  m.def("methods", &method_list,
        "Every registered method: name, family, order, stages, fixed_step, uses_jacobian, models, takes_form, "
        "legend, traits {symmetric, variational, stays_on_group, preserves_momentum_map, adaptive, "
        "must_complete_at_extremes, systems}.");
  m.def("simulate", &simulate_scene, py::arg("scene"), py::arg("method") = "lgvi", py::arg("model") = py::none(),
        py::arg("rtol") = py::none(), py::arg("atol") = py::none(), py::arg("csv") = py::none(),
        "Integrates a Scene with a method of methods() (baselines need model; adaptive ones take rtol/atol), "
        "as `lgvi-testbed simulate`. Returns {columns: {name: array} (every CSV column), t, R (n, 3, 3), Omega "
        "(n, 3) [x, v; R1, R2, Omega1, Omega2 for two bodies], metadata, summary (the run's JSON summary as a "
        "dict), csv}. The CSV is kept at `csv` if given.");

  m.def("suites", &ex::suite_list, "The suites: (name, description) pairs.");
  m.def("suite_cases", &suite_cases, py::arg("name"), py::arg("quick") = true, py::arg("scenes_dir") = py::none(),
        "The cases of a suite (id, group, expected, labels, timed), as `suite NAME --list`.");
  m.def("run_suite", &run_suite, py::arg("name"), py::arg("out"), py::arg("quick") = true, py::arg("jobs") = 1,
        py::arg("shard") = py::none(), py::arg("plots") = false, py::arg("formats") = py::none(),
        py::arg("scenes_dir") = py::none(), py::arg("progress") = false,
        "Runs a suite into the directory `out`, as `lgvi-testbed suite NAME --out OUT`; returns the summary's "
        "rows (summary.jsonl) as a list of dicts, in case order. shard: 'i/N'. progress: print the progress "
        "lines to stderr afterwards.");

  m.def("metric_groups", &ex::metric_groups, "validate's metric groups: (name, description) pairs.");
  m.def("validate", &validate, py::arg("quick") = true, py::arg("only") = std::vector<std::string>{},
        py::arg("accepted") = py::none(), py::arg("scenes_dir") = py::none(),
        "The regression gate, as `lgvi-testbed validate`: computes the metrics of the groups `only` (default "
        "all) and compares them with the accepted file (default the shipped one of the form). Returns {form, "
        "accepted_file, accepted_at, version, rows: [{name, kind, paper, accepted, now, verdict, seconds, "
        "detail}], counts: {verdict: n}, regressed, table}. Accepting stays with the CLI.");

  m.def("_set_data_root", [](const fs::path& root) { ex::set_data_root(root); }, py::arg("root"),
        "Makes the harness read its shipped data (scenes, studies, plot scripts, accepted metrics) from root "
        "(the installed package's data folder; called by lgvi/__init__.py).");
  m.def("data_dirs",
        [] {
          py::dict d;
          d["scenes"] = ex::default_scenes_dir();
          d["studies"] = ex::default_studies_dir();
          d["plots"] = ex::default_plots_dir();
          d["validation"] = ex::data_dir("validation", "validation");
          return d;
        },
        "Where the shipped data is read from: {scenes, studies, plots, validation} (the installed package's "
        "data folder, or the source tree's for a build tree's module).");
  m.def("run_study", &run_study, py::arg("study"), py::arg("out"), py::arg("quick") = true, py::arg("jobs") = 1,
        py::arg("shard") = py::none(), py::arg("plots") = false, py::arg("formats") = py::none(),
        py::arg("scenes_dir") = py::none(), py::arg("progress") = false, py::arg("sample") = py::none(),
        "Runs a study (a path, or a shipped study's name: data_dirs()['studies']) into the directory `out`, as "
        "`lgvi-testbed study FILE --out OUT`; returns the summary's rows (summary.jsonl) as a list of dicts, in "
        "case order. quick: the study's [quick] table; shard: 'i/N'; plots: draw the figures and tables (formats "
        "'png', 'pdf', 'svg' or a list 'png,pdf'); progress: print the progress lines to stderr afterwards; "
        "sample: a study with an [ensemble]: only sample K (--sample K).");
  m.def("study_statistics", &study_statistics, py::arg("out"),
        "The statistics over the samples of the ensemble study run into `out` (computed from OUT/summary.csv as "
        "NAME-statistics.csv is: per group, method label and setting, one entry per metric), as a dict of columns "
        "(lists): group, label, method, model, h, rtol, metric (str), samples, completed, count (int), median, q05, "
        "q25, q75, q95, max (float, NaN without values), failures, failing_samples (str).");
  m.def("solve_ocp", &solve_ocp, py::arg("system"),
        "Optimal control, as `lgvi-testbed ocp SYSTEM`: the paper's 'pendulum', 'dumbbell' (indirect shooting) or "
        "'cart-pendulum', 'connected-bodies' (direct method; solver='slsqp', 'ipopt' or 'ddp'), or a scene with an [ocp] "
        "table (a name or a path). Keyword options are "
        "the CLI's with underscores: form, h, steps, decomposition, merit, globalization, lm_damping, "
        "nonmonotone_memory, guess, max_iterations, t_final, sphere_radius, knots, spline, gradients, tolerance, "
        "starts, seed, first_start, solver, hessian, state_guess, shooting_interval (each checked against the "
        "CLI's range: ValueError naming it); out: keep the files in this directory. Returns "
        "{summary (the JSON summary), trajectory, history [, knots] (column dicts), converged, out}. "
        "ValueError for bad input.");
}
