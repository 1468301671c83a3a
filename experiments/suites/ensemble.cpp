#include "experiments/suites/ensemble.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <variant>

#include <Eigen/Geometry>

#include "experiments/scene/scene_table.hpp"
#include "experiments/systems/systems.hpp"
#include "lgvi/so3.hpp"

namespace lgvi::experiments {

namespace fs = std::filesystem;

double SplitMix64::normal() {
  const double u1 = 1.0 - uniform();  // (0, 1]: the logarithm is finite
  const double u2 = uniform();
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
}

std::uint64_t sample_seed(std::uint64_t seed, std::uint64_t k) {
  return SplitMix64::mix(seed ^ SplitMix64::mix(k + 0x9E3779B97F4A7C15ULL));
}

namespace {

constexpr std::string_view kEnsembleKeys[] = {"samples", "seed", "attitude", "omega", "moments", "values"};
constexpr std::string_view kAttitudeKeys[] = {"law", "spread"};
constexpr std::string_view kOmegaKeys[] = {"norm", "direction", "spread"};
constexpr std::string_view kMomentsKeys[] = {"law", "range"};
constexpr std::string_view kLawKeys[] = {"uniform", "normal"};
/// Samples of one ensemble: at most 10^7 (a study's cases are held in memory).
constexpr double kMaxSamples = 1e7;

/// [lo, hi] of numbers, lo <= hi (an empty range is an error), lo >= min.
std::pair<double, double> read_range(const TomlReader& r, const toml::node& n, const std::string& field, double min,
                                     bool min_open, const char* what) {
  const toml::array* a = n.as_array();
  if (a == nullptr || a->size() != 2) {
    r.fail(field, std::string("must be a range [lo, hi] of ") + what + " (got " + r.describe(n) + ")");
  }
  const double lo = r.finite_number(*a->get(0), field + "[0]");
  const double hi = r.finite_number(*a->get(1), field + "[1]");
  if (lo > hi) r.fail(field, "is an empty range (lo " + format_number(lo) + " > hi " + format_number(hi) + ")");
  if (min_open ? !(lo > min) : !(lo >= min)) {
    r.fail(field + "[0]", std::string("must be ") + (min_open ? "> " : ">= ") + format_number(min) + ": " + what +
                              " (got " + format_number(lo) + ")");
  }
  return {lo, hi};
}

/// An angle in [0, pi] (radians).
double read_spread(const TomlReader& r, const toml::node& n, const std::string& field) {
  const double s = r.finite_number(n, field);
  if (s < 0.0) r.fail(field, "is a negative spread (got " + format_number(s) + "); give an angle in [0, pi] radians");
  if (s > std::numbers::pi) r.fail(field, "must be an angle in [0, pi] radians (got " + format_number(s) + ")");
  return s;
}

/// "parameters.mass" -> (parameters, mass), "parameters.rho[2]" -> (parameters, rho, 2).
ScalarDispersion parse_value_name(const TomlReader& r, const std::string& name, const std::string& field) {
  ScalarDispersion d;
  d.name = name;
  d.field = field;
  const std::size_t dot = name.find('.');
  const auto bad = [&] {
    r.fail(field, "'" + name + "': name a number of the scene file as TABLE.KEY or TABLE.KEY[i], TABLE parameters "
                  "or initial (e.g. \"parameters.mass\", \"parameters.rho[2]\")");
  };
  if (dot == std::string::npos) bad();
  d.table = name.substr(0, dot);
  std::string key = name.substr(dot + 1);
  if (d.table != "parameters" && d.table != "initial") bad();
  if (const std::size_t open = key.find('['); open != std::string::npos) {
    if (key.back() != ']' || open + 2 > key.size() - 1) bad();
    const std::string digits = key.substr(open + 1, key.size() - open - 2);
    if (digits.empty() || digits.size() > 3 || !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; })) bad();
    d.index = static_cast<std::size_t>(std::stoul(digits));
    key = key.substr(0, open);
  }
  if (key.empty() || key.find_first_of(".[]") != std::string::npos) bad();
  d.key = key;
  return d;
}

ScalarLaw read_law(const TomlReader& r, const toml::node& n, const std::string& field) {
  const toml::table* t = n.as_table();
  if (t == nullptr || t->size() != 1) {
    r.fail(field, std::string("must be a table with one law, { uniform = [lo, hi] } or { normal = [mean, sd] } (got ") +
                      r.describe(n) + ")");
  }
  r.check_keys(*t, field, kLawKeys);
  ScalarLaw law;
  if (const toml::node* u = t->get("uniform")) {
    const auto [lo, hi] = read_range(r, *u, field + ".uniform", -INFINITY, false, "numbers");
    law = {ScalarLaw::Kind::Uniform, lo, hi};
  } else {
    const toml::node& nn = *t->get("normal");
    const toml::array* a = nn.as_array();
    if (a == nullptr || a->size() != 2) {
      r.fail(field + ".normal", "must be [mean, standard deviation] (got " + r.describe(nn) + ")");
    }
    const double mean = r.finite_number(*a->get(0), field + ".normal[0]");
    const double sd = r.finite_number(*a->get(1), field + ".normal[1]");
    if (sd < 0.0) r.fail(field + ".normal[1]", "is a negative spread (standard deviation " + format_number(sd) + ")");
    law = {ScalarLaw::Kind::Normal, mean, sd};
  }
  return law;
}

/// The model's attitude and body rate, when its system is one body with both.
template <class M>
constexpr bool kHasAttitude = requires(const M& m) {
  m.initial.R;
  m.initial.Omega;
};
bool has_attitude(const Model& model) {
  return std::visit([](const auto& m) { return kHasAttitude<std::decay_t<decltype(m)>>; }, model);
}
std::pair<Mat3, Vec3> attitude_and_rate(const Model& model) {
  return std::visit(
      [](const auto& m) -> std::pair<Mat3, Vec3> {
        if constexpr (kHasAttitude<std::decay_t<decltype(m)>>) {
          return {m.initial.R, m.initial.Omega};
        } else {
          return {Mat3::Identity(), Vec3::Zero()};
        }
      },
      model);
}

/// A unit vector uniform on the sphere (z uniform in [-1, 1], azimuth uniform: Archimedes).
Vec3 uniform_direction(SplitMix64& g) {
  const double z = 2.0 * g.uniform() - 1.0;
  const double phi = 2.0 * std::numbers::pi * g.uniform();
  const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {s * std::cos(phi), s * std::sin(phi), z};
}

/// A unit vector uniform on the cap of half-angle `spread` about the unit vector `axis`
/// (cos theta uniform in [cos spread, 1], azimuth uniform).
Vec3 direction_in_cap(SplitMix64& g, const Vec3& axis, double spread) {
  const double c = 1.0 - (1.0 - std::cos(spread)) * g.uniform();
  const double phi = 2.0 * std::numbers::pi * g.uniform();
  const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
  // An orthonormal pair normal to the axis.
  const Vec3 helper = std::abs(axis.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  const Vec3 u = axis.cross(helper).normalized();
  const Vec3 v = axis.cross(u);
  return c * axis + s * (std::cos(phi) * u + std::sin(phi) * v);
}

}  // namespace

EnsembleLaws read_ensemble(const TomlReader& r, const std::vector<EnsembleLayer>& layers) {
  // The keys with the field each is named by: a later layer's replace the same keys.
  std::map<std::string, std::pair<const toml::node*, std::string>> keys;
  std::string field = "ensemble";
  for (const EnsembleLayer& layer : layers) {
    if (layer.node == nullptr) continue;
    const toml::table* t = layer.node->as_table();
    if (t == nullptr) r.fail(layer.field, std::string("must be a table (got ") + r.describe(*layer.node) + ")");
    r.check_keys(*t, layer.field, kEnsembleKeys);
    for (auto&& [k, v] : *t) keys[std::string(k.str())] = {&v, layer.field + "." + std::string(k.str())};
    if (field == "ensemble") field = layer.field;
  }
  const auto get = [&](const char* key) -> std::pair<const toml::node*, std::string> {
    const auto it = keys.find(key);
    return it == keys.end() ? std::make_pair(nullptr, field + "." + key) : it->second;
  };

  EnsembleLaws laws;
  laws.field = field;
  {
    const auto [node, f] = get("samples");
    if (node == nullptr) r.fail(f, "is required (the number of samples N >= 1)");
    const std::int64_t v = r.integer(*node, f);
    if (v < 1 || static_cast<double>(v) > kMaxSamples) {
      r.fail(f, "must be an integer in [1, 10000000] (got " + std::to_string(v) + "): the number of samples");
    }
    laws.samples = v;
  }
  {
    const auto [node, f] = get("seed");
    if (node == nullptr) r.fail(f, "is required (an integer >= 0: sample k's generator is seeded from (seed, k))");
    const std::int64_t v = r.integer(*node, f);
    if (v < 0) r.fail(f, "must be an integer >= 0 (got " + std::to_string(v) + ")");
    laws.seed = static_cast<std::uint64_t>(v);
  }
  if (const auto [node, f] = get("attitude"); node != nullptr) {
    laws.attitude_field = f;
    std::string law;
    const toml::table* a = node->as_table();
    if (node->is_string()) {
      law = r.string(*node, f);
    } else if (a != nullptr) {
      r.check_keys(*a, f, kAttitudeKeys);
      const toml::node* l = a->get("law");
      if (l == nullptr) r.fail(f + ".law", "is required (\"uniform\" or \"about-nominal\")");
      law = r.string(*l, f + ".law");
    } else {
      r.fail(f, std::string("must be \"uniform\" or a table { law, spread } (got ") + r.describe(*node) + ")");
    }
    if (law == "uniform") {
      laws.attitude = EnsembleLaws::Attitude::Uniform;
      if (a != nullptr && a->get("spread") != nullptr) r.fail(f + ".spread", "applies to law \"about-nominal\" only");
    } else if (law == "about-nominal") {
      laws.attitude = EnsembleLaws::Attitude::AboutNominal;
      const toml::node* s = a == nullptr ? nullptr : a->get("spread");
      if (s == nullptr) r.fail(f + ".spread", "is required for \"about-nominal\" (the largest angle, radians, in [0, pi])");
      laws.attitude_spread = read_spread(r, *s, f + ".spread");
    } else {
      r.fail(a != nullptr ? f + ".law" : f, "unknown law '" + law + "' (expected \"uniform\" or \"about-nominal\")");
    }
  }
  if (const auto [node, f] = get("omega"); node != nullptr) {
    laws.omega_field = f;
    laws.omega = true;
    const toml::table* o = node->as_table();
    if (o == nullptr) r.fail(f, std::string("must be a table { norm, direction, spread } (got ") + r.describe(*node) + ")");
    r.check_keys(*o, f, kOmegaKeys);
    if (const toml::node* nr = o->get("norm")) {
      const auto [lo, hi] = read_range(r, *nr, f + ".norm", 0.0, false, "rates, rad/s, >= 0");
      laws.omega_norm_lo = lo;
      laws.omega_norm_hi = hi;
    }
    std::string direction = "uniform";
    if (const toml::node* d = o->get("direction")) direction = r.string(*d, f + ".direction");
    if (direction == "uniform") {
      if (o->get("spread") != nullptr) r.fail(f + ".spread", "applies to direction \"about-nominal\" only");
    } else if (direction == "about-nominal") {
      laws.omega_uniform_direction = false;
      const toml::node* s = o->get("spread");
      if (s == nullptr) r.fail(f + ".spread", "is required for direction \"about-nominal\" (the cap's half-angle, radians)");
      laws.omega_spread = read_spread(r, *s, f + ".spread");
    } else {
      r.fail(f + ".direction", "unknown law '" + direction + "' (expected \"uniform\" or \"about-nominal\")");
    }
  }
  if (const auto [node, f] = get("moments"); node != nullptr) {
    laws.moments_field = f;
    laws.moments = true;
    const toml::table* m = node->as_table();
    if (m == nullptr) r.fail(f, std::string("must be a table { range = [lo, hi] } (got ") + r.describe(*node) + ")");
    r.check_keys(*m, f, kMomentsKeys);
    if (const toml::node* l = m->get("law")) {
      const std::string law = r.string(*l, f + ".law");
      if (law != "triangle-uniform") r.fail(f + ".law", "unknown law '" + law + "' (expected \"triangle-uniform\")");
    }
    const toml::node* range = m->get("range");
    if (range == nullptr) r.fail(f + ".range", "is required (the principal moments' range [lo, hi], lo > 0)");
    const auto [lo, hi] = read_range(r, *range, f + ".range", 0.0, true, "principal moments");
    if (lo < kMinSceneMagnitude || hi > kMaxSceneMagnitude) {
      r.fail(f + ".range", "must lie between 1e-100 and 1e100 (the scene files' range of numbers)");
    }
    laws.moments_lo = lo;
    laws.moments_hi = hi;
  }
  if (const auto [node, f] = get("values"); node != nullptr) {
    const toml::table* v = node->as_table();
    if (v == nullptr) {
      r.fail(f, std::string("must be a table { \"TABLE.KEY\" = { uniform = [lo, hi] } | { normal = [mean, sd] } } (got ") +
                    r.describe(*node) + ")");
    }
    for (auto&& [k, law] : *v) {
      const std::string name(k.str());
      const std::string vf = f + ".\"" + name + "\"";
      ScalarDispersion d = parse_value_name(r, name, vf);
      d.law = read_law(r, law, vf);
      const auto clash = [&](const char* table, std::initializer_list<const char*> names, bool given, const std::string& by) {
        if (!given || d.table != table) return;
        for (const char* x : names) {
          if (d.key == x) r.fail(vf, "is drawn by " + by + " already");
        }
      };
      clash("initial", {"R", "quaternion", "euler"}, laws.attitude != EnsembleLaws::Attitude::File, laws.attitude_field);
      clash("initial", {"Omega", "omega_space"}, laws.omega, laws.omega_field);
      clash("parameters", {"inertia"}, laws.moments, laws.moments_field);
      laws.values.push_back(std::move(d));
    }
  }
  return laws;
}

void check_ensemble(const TomlReader& r, const EnsembleLaws& laws, const Scene& nominal, const toml::table& doc) {
  const std::string about = "scene '" + nominal.name + "' (" + nominal.system() + ")";
  if ((laws.attitude != EnsembleLaws::Attitude::File || laws.omega) && !has_attitude(nominal.model)) {
    r.fail(laws.attitude != EnsembleLaws::Attitude::File ? laws.attitude_field : laws.omega_field,
           about + " cannot take it: its system is not one body with an attitude R and a body rate Omega");
  }
  if (laws.omega && !laws.omega_uniform_direction && attitude_and_rate(nominal.model).second.norm() == 0.0) {
    r.fail(laws.omega_field + ".direction", about + " has Omega = 0: no direction to spread about");
  }
  const toml::table* parameters = doc.get_as<toml::table>("parameters");
  if (laws.moments && (parameters == nullptr || parameters->get("inertia") == nullptr)) {
    r.fail(laws.moments_field, about + " cannot take it: its file has no [parameters] inertia (a body's principal moments)");
  }
  for (const ScalarDispersion& d : laws.values) {
    const toml::table* t = doc.get_as<toml::table>(d.table);
    const toml::node* n = t == nullptr ? nullptr : t->get(d.key);
    if (n != nullptr && d.index) {
      const toml::array* a = n->as_array();
      n = a == nullptr || *d.index >= a->size() ? nullptr : a->get(*d.index);
    }
    if (n == nullptr || !(n->is_floating_point() || n->is_integer())) {
      r.fail(d.field, about + " has no number at " + d.name + " in its file (" + nominal.file.filename().string() +
                          "): a law replaces a number the file gives");
    }
  }
}

std::vector<std::string> drawn_columns(const EnsembleLaws& laws) {
  std::vector<std::string> c;
  const auto add = [&](const std::string& name, int n) {
    for (int i = 0; i < n; ++i) c.push_back(name + "[" + std::to_string(i) + "]");
  };
  if (laws.attitude != EnsembleLaws::Attitude::File) add("initial.quaternion", 4);
  if (laws.omega) add("initial.Omega", 3);
  if (laws.moments) add("parameters.inertia", 3);
  for (const ScalarDispersion& d : laws.values) c.push_back(d.name);
  return c;
}

EnsembleSample::EnsembleSample(std::shared_ptr<const toml::table> doc, const EnsembleLaws& laws, const Scene& nominal,
                               std::uint64_t k)
    : doc_(std::move(doc)), k_(k) {
  const std::uint64_t seed = sample_seed(laws.seed, k);
  SplitMix64 g(seed);
  fields_.push_back({"sample", static_cast<std::int64_t>(k)});
  fields_.push_back({"sample_seed", std::to_string(seed)});
  const std::vector<std::string> names = drawn_columns(laws);
  std::size_t name = 0;
  const auto record = [&](const std::vector<double>& values) {
    for (const double v : values) fields_.push_back({names[name++], v});
  };
  const auto [R0, Omega0] = attitude_and_rate(nominal.model);
  if (laws.attitude != EnsembleLaws::Attitude::File) {
    Eigen::Quaterniond q;
    if (laws.attitude == EnsembleLaws::Attitude::Uniform) {
      // Shoemake, "Uniform random rotations", Graphics Gems III (1992): with u1, u2, u3 uniform
      // in [0, 1), (sqrt(1-u1) sin 2pi u2, sqrt(1-u1) cos 2pi u2, sqrt(u1) sin 2pi u3,
      // sqrt(u1) cos 2pi u3) is uniform on S^3, hence its rotation uniform (Haar) on SO(3).
      const double u1 = g.uniform(), u2 = g.uniform(), u3 = g.uniform();
      const double a = std::sqrt(1.0 - u1), b = std::sqrt(u1);
      const double t2 = 2.0 * std::numbers::pi * u2, t3 = 2.0 * std::numbers::pi * u3;
      q = Eigen::Quaterniond(b * std::cos(t3), a * std::sin(t2), a * std::cos(t2), b * std::sin(t3));
    } else {
      // R0 exp(hat(theta a)): a uniform on the sphere, theta uniform in [0, spread].
      const Vec3 axis = uniform_direction(g);
      const double theta = laws.attitude_spread * g.uniform();
      q = Eigen::Quaterniond(R0) * Eigen::Quaterniond(Eigen::AngleAxisd(theta, axis));
    }
    q.normalize();
    if (q.w() < 0.0) q.coeffs() = -q.coeffs();  // one of +-q: scalar part >= 0
    const std::vector<double> wxyz = {q.w(), q.x(), q.y(), q.z()};
    edits_.push_back({"initial", "quaternion", {"R", "quaternion", "euler"}, std::nullopt, wxyz});
    record(wxyz);
  }
  if (laws.omega) {
    const double lo = laws.omega_norm_lo.value_or(Omega0.norm());
    const double hi = laws.omega_norm_hi.value_or(Omega0.norm());
    const double norm = lo + (hi - lo) * g.uniform();
    const Vec3 direction = laws.omega_uniform_direction ? uniform_direction(g)
                                                        : direction_in_cap(g, Omega0.normalized(), laws.omega_spread);
    const Vec3 w = norm * direction;
    const std::vector<double> v = {w.x(), w.y(), w.z()};
    edits_.push_back({"initial", "Omega", {"Omega", "omega_space"}, std::nullopt, v});
    record(v);
  }
  if (laws.moments) {
    Vec3 J;
    do {
      for (int i = 0; i < 3; ++i) J(i) = laws.moments_lo + (laws.moments_hi - laws.moments_lo) * g.uniform();
    } while (J(0) > J(1) + J(2) || J(1) > J(0) + J(2) || J(2) > J(0) + J(1));
    const std::vector<double> v = {J.x(), J.y(), J.z()};
    edits_.push_back({"parameters", "inertia", {"inertia"}, std::nullopt, v});
    record(v);
  }
  for (const ScalarDispersion& d : laws.values) {
    const double x = d.law.draw(g);
    edits_.push_back({d.table, d.key, {}, d.index, {x}});
    record({x});
  }
}

Scene EnsembleSample::load(const fs::path& file, const SceneOverrides& overrides) const {
  toml::table doc = *doc_;
  for (const Edit& e : edits_) {
    toml::table* t = doc.get_as<toml::table>(e.table);
    if (t == nullptr) t = doc.insert_or_assign(e.table, toml::table{}).first->second.as_table();
    for (const std::string& key : e.remove) t->erase(key);
    if (e.index) {
      toml::array& a = *t->get_as<toml::array>(e.key);  // check_ensemble: an array with that element
      a.replace(a.cbegin() + static_cast<std::ptrdiff_t>(*e.index), e.values.front());
    } else if (e.values.size() == 1) {
      t->insert_or_assign(e.key, e.values.front());
    } else {
      toml::array a;
      for (const double v : e.values) a.push_back(v);
      t->insert_or_assign(e.key, std::move(a));
    }
  }
  return parse_scene_table(doc, "", file, overrides);
}

}  // namespace lgvi::experiments
