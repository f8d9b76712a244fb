#include "cga_rigid_sim/cga/multivector.h"

#include <algorithm>
#include <cmath>
#include <ostream>
#include <stdexcept>

namespace cga_rigid_sim {
namespace cga {

namespace {

constexpr unsigned kNumBasisVectors = 5;
constexpr unsigned kNumBlades = Multivector::kNumBlades;

// Squares of the basis vectors e1, e2, e3, e, ē (signature (4,1)).
constexpr int kBasisSquare[kNumBasisVectors] = {+1, +1, +1, +1, -1};

constexpr int bitCount(unsigned x) {
  int count = 0;
  for (; x != 0; x &= x - 1) ++count;
  return count;
}

// Sign of blade(a) * blade(b) = sign · blade(a XOR b).
// Write the product as the word (factors of a)(factors of b), each part in increasing order.
// Sorting the word takes one swap for every pair (factor of a, factor of b) that is out of
// order, i.e. for each factor e_i of b, one swap per factor of a with a larger index; each swap
// of distinct orthogonal basis vectors flips the sign. The shared factors then stand next to
// each other in pairs e_i e_i, and each pair contracts to the square of e_i.
constexpr int productSign(unsigned a, unsigned b) {
  int swaps = 0;
  for (unsigned i = 0; i < kNumBasisVectors; ++i) {
    if ((b >> i) & 1u) swaps += bitCount(a >> (i + 1));
  }
  int sign = (swaps % 2 == 0) ? 1 : -1;
  for (unsigned i = 0; i < kNumBasisVectors; ++i) {
    if (((a & b) >> i) & 1u) sign *= kBasisSquare[i];
  }
  return sign;
}

using SignTable = std::array<std::array<int, kNumBlades>, kNumBlades>;

constexpr SignTable makeSignTable() {
  SignTable table{};
  for (unsigned a = 0; a < kNumBlades; ++a) {
    for (unsigned b = 0; b < kNumBlades; ++b) table[a][b] = productSign(a, b);
  }
  return table;
}

// Computed at compile time: no static-initialisation order to worry about.
constexpr SignTable kSignTable = makeSignTable();

// A few entries worked by hand: e1e2 = e12, e2e1 = −e12, ēē = −1, (e1e2)(e1e2) = −1,
// e2 (e1e3) = −e123.
static_assert(kSignTable[1][2] == +1, "e1 e2 = +e12");
static_assert(kSignTable[2][1] == -1, "e2 e1 = -e12");
static_assert(kSignTable[16][16] == -1, "ebar^2 = -1");
static_assert(kSignTable[3][3] == -1, "(e12)^2 = -1");
static_assert(kSignTable[2][5] == -1, "e2 e13 = -e123");

const char* const kBasisVectorName[kNumBasisVectors] = {"e1", "e2", "e3", "e4", "e5"};

}  // namespace

Multivector::Multivector() { coeffs_.fill(0.0); }

Multivector Multivector::scalar(double s) { return blade(0, s); }

Multivector Multivector::blade(unsigned mask, double coeff) {
  Multivector m;
  m[mask] = coeff;
  return m;
}

Multivector Multivector::vector(double e1, double e2, double e3, double e, double ebar) {
  Multivector m;
  m[kE1] = e1;
  m[kE2] = e2;
  m[kE3] = e3;
  m[kE] = e;
  m[kEbar] = ebar;
  return m;
}

Multivector Multivector::e1() { return blade(kE1); }
Multivector Multivector::e2() { return blade(kE2); }
Multivector Multivector::e3() { return blade(kE3); }
Multivector Multivector::e() { return blade(kE); }
Multivector Multivector::ebar() { return blade(kEbar); }
Multivector Multivector::n() { return e() + ebar(); }
Multivector Multivector::nbar() { return e() - ebar(); }
Multivector Multivector::I3() { return blade(kE1 | kE2 | kE3); }

double& Multivector::operator[](unsigned mask) { return coeffs_.at(mask); }
double Multivector::operator[](unsigned mask) const { return coeffs_.at(mask); }

Multivector& Multivector::operator+=(const Multivector& b) {
  for (unsigned i = 0; i < kNumBlades; ++i) coeffs_[i] += b.coeffs_[i];
  return *this;
}

Multivector& Multivector::operator-=(const Multivector& b) {
  for (unsigned i = 0; i < kNumBlades; ++i) coeffs_[i] -= b.coeffs_[i];
  return *this;
}

Multivector& Multivector::operator*=(double s) {
  for (double& c : coeffs_) c *= s;
  return *this;
}

Multivector& Multivector::operator/=(double s) {
  for (double& c : coeffs_) c /= s;
  return *this;
}

Multivector Multivector::reverse() const {
  Multivector r = *this;
  for (unsigned i = 0; i < kNumBlades; ++i) {
    const int k = bladeGrade(i);
    if ((k * (k - 1) / 2) % 2 != 0) r.coeffs_[i] = -r.coeffs_[i];
  }
  return r;
}

Multivector Multivector::gradeInvolution() const {
  Multivector r = *this;
  for (unsigned i = 0; i < kNumBlades; ++i) {
    if (bladeGrade(i) % 2 != 0) r.coeffs_[i] = -r.coeffs_[i];
  }
  return r;
}

Multivector Multivector::grade(int k) const {
  Multivector r;
  for (unsigned i = 0; i < kNumBlades; ++i) {
    if (bladeGrade(i) == k) r.coeffs_[i] = coeffs_[i];
  }
  return r;
}

double Multivector::scalarPart() const { return coeffs_[0]; }

double Multivector::norm2() const {
  double sum = 0.0;
  for (double c : coeffs_) sum += c * c;
  return std::sqrt(sum);
}

int Multivector::bladeGrade(unsigned mask) { return bitCount(mask); }

int basisProductSign(unsigned a, unsigned b) { return kSignTable.at(a).at(b); }

Multivector operator+(const Multivector& a, const Multivector& b) {
  Multivector r = a;
  r += b;
  return r;
}

Multivector operator-(const Multivector& a, const Multivector& b) {
  Multivector r = a;
  r -= b;
  return r;
}

Multivector operator-(const Multivector& a) { return -1.0 * a; }

Multivector operator+(double s, const Multivector& a) { return Multivector::scalar(s) + a; }
Multivector operator+(const Multivector& a, double s) { return a + Multivector::scalar(s); }
Multivector operator-(double s, const Multivector& a) { return Multivector::scalar(s) - a; }
Multivector operator-(const Multivector& a, double s) { return a - Multivector::scalar(s); }

Multivector operator*(double s, const Multivector& a) {
  Multivector r = a;
  r *= s;
  return r;
}

Multivector operator*(const Multivector& a, double s) { return s * a; }

Multivector operator/(const Multivector& a, double s) {
  Multivector r = a;
  r /= s;
  return r;
}

// Bilinear extension of the basis-blade product: blade(i) blade(j) = sign(i, j) blade(i ^ j).
Multivector operator*(const Multivector& a, const Multivector& b) {
  Multivector r;
  for (unsigned i = 0; i < kNumBlades; ++i) {
    for (unsigned j = 0; j < kNumBlades; ++j) {
      r[i ^ j] += kSignTable[i][j] * a[i] * b[j];
    }
  }
  return r;
}

Multivector operator^(const Multivector& a, const Multivector& b) { return outer(a, b); }

// The three grade-selecting products, literally from their definitions on the homogeneous parts.
Multivector outer(const Multivector& a, const Multivector& b) {
  Multivector r;
  for (int ra = 0; ra <= 5; ++ra) {
    for (int sb = 0; sb <= 5; ++sb) r += (a.grade(ra) * b.grade(sb)).grade(ra + sb);
  }
  return r;
}

Multivector inner(const Multivector& a, const Multivector& b) {
  Multivector r;
  for (int ra = 1; ra <= 5; ++ra) {
    for (int sb = 1; sb <= 5; ++sb) r += (a.grade(ra) * b.grade(sb)).grade(std::abs(ra - sb));
  }
  return r;
}

Multivector leftContract(const Multivector& a, const Multivector& b) {
  Multivector r;
  for (int ra = 0; ra <= 5; ++ra) {
    for (int sb = ra; sb <= 5; ++sb) r += (a.grade(ra) * b.grade(sb)).grade(sb - ra);
  }
  return r;
}

Multivector commutator(const Multivector& a, const Multivector& b) { return 0.5 * (a * b - b * a); }

double maxAbsDiff(const Multivector& a, const Multivector& b) {
  double m = 0.0;
  for (unsigned i = 0; i < kNumBlades; ++i) m = std::max(m, std::abs(a[i] - b[i]));
  return m;
}

Multivector expSeries(const Multivector& a, int terms) {
  Multivector sum;
  Multivector term = Multivector::scalar(1.0);  // a^k / k!
  for (int k = 0; k < terms; ++k) {
    sum += term;
    term = term * a / static_cast<double>(k + 1);
  }
  return sum;
}

std::ostream& operator<<(std::ostream& os, const Multivector& a) {
  bool first = true;
  for (int k = 0; k <= 5; ++k) {
    for (unsigned mask = 0; mask < kNumBlades; ++mask) {
      if (Multivector::bladeGrade(mask) != k || a[mask] == 0.0) continue;
      const double c = a[mask];
      if (first) {
        os << c;
      } else {
        os << (c < 0 ? " - " : " + ") << std::abs(c);
      }
      first = false;
      // Blade name: its factors in increasing order, joined by ^.
      const char* separator = "*";
      for (unsigned i = 0; i < kNumBasisVectors; ++i) {
        if ((mask >> i) & 1u) {
          os << separator << kBasisVectorName[i];
          separator = "^";
        }
      }
    }
  }
  if (first) os << 0;
  return os;
}

}  // namespace cga
}  // namespace cga_rigid_sim
