#include "compiler/builtins.hpp"

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace snell::compile {
namespace {

enum class Id {
#define SNELL_BUILTIN(name, arity, sig) name,
#include "compiler/builtins.def"
};

constexpr BuiltinInfo kBuiltins[] = {
#define SNELL_BUILTIN(name, arity, sig) {#name, arity, sig},
#include "compiler/builtins.def"
};

constexpr double kDeg = 3.14159265358979323846 / 180.0;

// sin/cos in degrees, exact at multiples of 90 so that cos(90) == 0.
double sin_deg(double d) {
  double s, c;
  ir::detail::sincos_degrees(d, s, c);
  return s;
}
double cos_deg(double d) {
  double s, c;
  ir::detail::sincos_degrees(d, s, c);
  return c;
}
double tan_deg(double d) {
  double s, c;
  ir::detail::sincos_degrees(d, s, c);
  return s / c;  // tan(90) = ±inf: reported by the caller as non-finite
}

// Shape of a component-wise call: the common vector size of the arguments.
bool common_dims(const Value* args, int n, int& dims, BuiltinError& err) {
  dims = 1;
  for (int i = 0; i < n; ++i) {
    if (args[i].type != Type::Number && !args[i].is_vector()) {
      err = {i, "expects a number or a vector, got a " + std::string(type_name(args[i].type))};
      return false;
    }
    int d = args[i].dims();
    if (d == 1) continue;
    if (dims != 1 && d != dims) {
      err = {i, "mixes a 2-vector and a 3-vector"};
      return false;
    }
    dims = d;
  }
  return true;
}

double comp(const Value& v, int i) {
  return v.type == Type::Number ? v.n : v.v[i];
}

Value make(int dims, const double* c) {
  if (dims == 1) return Value::number(c[0]);
  if (dims == 2) return Value::vec2(c[0], c[1]);
  return Value::vec3({c[0], c[1], c[2]});
}

template <class F>
Value map(const Value* args, int n, BuiltinError& err, F f) {
  int dims;
  if (!common_dims(args, n, dims, err)) return Value::error();
  double out[3];
  for (int i = 0; i < dims; ++i) {
    double a = comp(args[0], i);
    double b = n > 1 ? comp(args[1], i) : 0;
    double c = n > 2 ? comp(args[2], i) : 0;
    out[i] = f(a, b, c);
  }
  return make(dims, out);
}

// One component of the component-wise builtins: the only place their arithmetic
// is written, so Value calls and the evaluator's numeric fast path agree bit for bit.
double scalar(int id, double x, double y, double t) {
  switch (static_cast<Id>(id)) {
    case Id::sin:
      return sin_deg(x);
    case Id::cos:
      return cos_deg(x);
    case Id::tan:
      return tan_deg(x);
    case Id::asin:
      return std::asin(x) / kDeg;
    case Id::acos:
      return std::acos(x) / kDeg;
    case Id::atan:
      return std::atan(x) / kDeg;
    case Id::atan2:
      return std::atan2(x, y) / kDeg;
    case Id::sqrt:
      return std::sqrt(x);
    case Id::pow:
      return std::pow(x, y);
    case Id::exp:
      return std::exp(x);
    case Id::log:
      return std::log(x);
    case Id::abs:
      return std::fabs(x);
    case Id::floor:
      return std::floor(x);
    case Id::ceil:
      return std::ceil(x);
    case Id::round:
      return std::round(x);
    case Id::min:
      return std::fmin(x, y);
    case Id::max:
      return std::fmax(x, y);
    case Id::clamp:
      return std::fmin(std::fmax(x, y), t);
    case Id::mix:
      return x * (1 - t) + y * t;
    default:
      return 0;
  }
}

}  // namespace

const unsigned char detail::kBuiltinArity[] = {
#define SNELL_BUILTIN(name, arity, sig) arity,
#include "compiler/builtins.def"
};

int builtin_count() {
  return static_cast<int>(std::size(kBuiltins));
}

int find_builtin(std::string_view name) {
  for (int i = 0; i < builtin_count(); ++i)
    if (kBuiltins[i].name == name) return i;
  return -1;
}

const BuiltinInfo& builtin_info(int id) {
  return kBuiltins[id];
}

double random_hash(double n) {
  if (n == 0) n = 0;  // -0 -> +0
  std::uint64_t z = std::bit_cast<std::uint64_t>(n);
  z += 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) * 0x1p-53;
}

bool call_builtin_number(int id, const double* a, double& out) {
  switch (static_cast<Id>(id)) {
    case Id::dot:
    case Id::cross:
    case Id::length:
    case Id::normalize:
      return false;
    case Id::random:
      out = random_hash(a[0]);
      return true;
    default:
      out = scalar(id, a[0], a[1], a[2]);
      return true;
  }
}

bool builtin_numeric(int id) {
  auto k = static_cast<Id>(id);
  return k != Id::dot && k != Id::cross && k != Id::length && k != Id::normalize;
}

Value call_builtin(int id, const Value* a, BuiltinError& err) {
  auto vec_arg = [&](int i) {
    if (!a[i].is_vector()) {
      err = {i, "expects a vector, got a " + std::string(type_name(a[i].type))};
      return false;
    }
    return true;
  };
  switch (static_cast<Id>(id)) {
    case Id::sin:
    case Id::cos:
    case Id::tan:
    case Id::asin:
    case Id::acos:
    case Id::atan:
    case Id::sqrt:
    case Id::exp:
    case Id::log:
    case Id::abs:
    case Id::floor:
    case Id::ceil:
    case Id::round:
      return map(a, 1, err, [id](double x, double, double) { return scalar(id, x, 0, 0); });
    case Id::atan2:
    case Id::pow:
    case Id::min:
    case Id::max:
      return map(a, 2, err, [id](double x, double y, double) { return scalar(id, x, y, 0); });
    case Id::clamp:
    case Id::mix:
      return map(a, 3, err, [id](double x, double y, double z) { return scalar(id, x, y, z); });
    case Id::dot:
      if (!vec_arg(0) || !vec_arg(1)) return Value::error();
      if (a[0].type != a[1].type) {
        err = {1, "dot of a " + std::string(type_name(a[0].type)) + " and a " +
                      std::string(type_name(a[1].type))};
        return Value::error();
      }
      return Value::number(ir::dot(a[0].v, a[1].v));
    case Id::cross:
      for (int i = 0; i < 2; ++i)
        if (a[i].type != Type::Vec3) {
          err = {i, "expects a 3-vector, got a " + std::string(type_name(a[i].type))};
          return Value::error();
        }
      return Value::vec3(ir::cross(a[0].v, a[1].v));
    case Id::length:
      if (!vec_arg(0)) return Value::error();
      return Value::number(ir::length(a[0].v));
    case Id::normalize: {
      if (!vec_arg(0)) return Value::error();
      double len = ir::length(a[0].v);
      if (len == 0) {
        err = {0, "cannot normalize a zero vector"};
        return Value::error();
      }
      Value r = a[0];
      r.v = r.v / len;
      return r;
    }
    case Id::random:
      if (a[0].type != Type::Number) {
        err = {0, "expects a number, got a " + std::string(type_name(a[0].type))};
        return Value::error();
      }
      return Value::number(random_hash(a[0].n));
  }
  return Value::error();
}

}  // namespace snell::compile
