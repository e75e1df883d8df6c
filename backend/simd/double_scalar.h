// Four lanes of double in plain C++: the reference Double4Sse and Double4Avx mirror. The kernels
// use them for the watertight test's double-precision second half of a block's four triangles;
// each lane computes what the scalar test (resolveWatertightHitOf) computes for that triangle.
#pragma once

namespace obvh::simd {

struct Double4Scalar {
  double v[4];

  static Double4Scalar broadcast(double x) { return {{x, x, x, x}}; }
  // Four floats, widened (exactly).
  static Double4Scalar widen(const float* p) { return {{double(p[0]), double(p[1]), double(p[2]), double(p[3])}}; }
  // Each lane rounded to the nearest float.
  void narrow(float* p) const {
    for (int i = 0; i < 4; ++i) p[i] = float(v[i]);
  }

  template <typename Op>
  static Double4Scalar map(const Double4Scalar& a, const Double4Scalar& b, Op op) {
    Double4Scalar r;
    for (int i = 0; i < 4; ++i) r.v[i] = op(a.v[i], b.v[i]);
    return r;
  }
  friend Double4Scalar operator+(Double4Scalar a, Double4Scalar b) { return map(a, b, [](double x, double y) { return x + y; }); }
  friend Double4Scalar operator-(Double4Scalar a, Double4Scalar b) { return map(a, b, [](double x, double y) { return x - y; }); }
  friend Double4Scalar operator*(Double4Scalar a, Double4Scalar b) { return map(a, b, [](double x, double y) { return x * y; }); }
  friend Double4Scalar operator/(Double4Scalar a, Double4Scalar b) { return map(a, b, [](double x, double y) { return x / y; }); }
  // Bit i set when lane i is zero (either sign).
  friend int zeroMask(Double4Scalar a) {
    int m = 0;
    for (int i = 0; i < 4; ++i) m |= int(a.v[i] == 0.0) << i;
    return m;
  }
};

}  // namespace obvh::simd
