#include "compiler/builtins.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>

#include "runtime/ir/scalar_math.hpp"
#include "runtime/pattern/noise.hpp"

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

// Shape of a component-wise call: the common vector size of the arguments.
bool common_dims(const Value* args, int n, int& dims, BuiltinError& err) {
  dims = 1;
  for (int i = 0; i < n; ++i) {
    if (args[i].type != Type::Number && !args[i].is_vector()) {
      err = {i, "expects a number or a vector, got " + a_type(args[i].type)};
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
  namespace m = ir::scalar;
  switch (static_cast<Id>(id)) {
    case Id::sin:
      return m::sin_deg(x);
    case Id::cos:
      return m::cos_deg(x);
    case Id::tan:
      return m::tan_deg(x);
    case Id::asin:
      return m::asin_deg(x);
    case Id::acos:
      return m::acos_deg(x);
    case Id::atan:
      return m::atan_deg(x);
    case Id::atan2:
      return m::atan2_deg(x, y);
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
      return m::clamp(x, y, t);
    case Id::mix:
      return m::mix(x, y, t);
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
  return ir::scalar::random_hash(n);
}

bool octaves_ok(const Value& v, int arg, BuiltinError& err) {
  if (v.type != Type::Number) {
    err = {arg, "expects a number of octaves, got " + a_type(v.type)};
    return false;
  }
  if (v.n != std::floor(v.n)) {
    err = {arg, "takes a whole number of octaves, not " + to_string(v),
           lang::DiagKind::NotAnInteger};
    return false;
  }
  if (v.n < 1 || v.n > pattern::kMaxOctaves) {
    err = {arg,
           "takes 1 to " + std::to_string(pattern::kMaxOctaves) + " octaves, not " + to_string(v),
           lang::DiagKind::InvalidValue};
    return false;
  }
  return true;
}

bool call_builtin_number(int id, const double* a, double& out) {
  if (!builtin_numeric(id)) return false;
  switch (static_cast<Id>(id)) {
    case Id::random:
      out = random_hash(a[0]);
      return true;
    default:
      out = scalar(id, a[0], a[1], a[2]);
      return true;
  }
}

bool builtin_numeric(int id) {
  switch (static_cast<Id>(id)) {
    case Id::dot:
    case Id::cross:
    case Id::length:
    case Id::normalize:
    case Id::noise:
    case Id::fbm:
    case Id::turbulence:
    case Id::cells:
      return false;
    default:
      return true;
  }
}

Value call_builtin(int id, const Value* a, BuiltinError& err) {
  auto vec3_arg = [&](int i) {
    if (a[i].type != Type::Vec3) {
      err = {i, "expects a 3-vector (a point), got " + a_type(a[i].type)};
      return false;
    }
    return true;
  };
  auto vec_arg = [&](int i) {
    if (!a[i].is_vector()) {
      err = {i, "expects a vector, got " + a_type(a[i].type)};
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
        err = {1, "dot of " + a_type(a[0].type) + " and " + a_type(a[1].type)};
        return Value::error();
      }
      return Value::number(ir::dot(a[0].v, a[1].v));
    case Id::cross:
      for (int i = 0; i < 2; ++i)
        if (a[i].type != Type::Vec3) {
          err = {i, "expects a 3-vector, got " + a_type(a[i].type)};
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
        err = {0, "expects a number, got " + a_type(a[0].type)};
        return Value::error();
      }
      return Value::number(random_hash(a[0].n));
    case Id::noise:
      if (!vec3_arg(0)) return Value::error();
      return Value::number(pattern::noise(a[0].v));
    case Id::cells:
      if (!vec3_arg(0)) return Value::error();
      return Value::number(pattern::cells(a[0].v));
    case Id::fbm:
    case Id::turbulence: {
      bool p_ok = vec3_arg(0);
      if (!p_ok || !octaves_ok(a[1], 1, err)) return Value::error();
      int oct = static_cast<int>(a[1].n);
      return Value::number(static_cast<Id>(id) == Id::fbm ? pattern::fbm(a[0].v, oct)
                                                          : pattern::turbulence(a[0].v, oct));
    }
  }
  return Value::error();
}

}  // namespace snell::compile
