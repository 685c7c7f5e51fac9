#pragma once
// An independent, deliberately naive reference for the orthogonal-array tests, written from the
// textbook definitions rather than from the library (Hedayat, Sloane and Stufken, "Orthogonal
// Arrays: Theory and Applications", 1999; Bose 1938; Bush 1952; Bose and Bush 1952; Addelman and
// Kempthorne 1961). Nothing here calls the oas_gf_* functions or any other library code.
//
//  - GF(p^k) as polynomials over GF(p) (coefficient vectors, index i <-> x^i) reduced modulo a
//    monic f(x) = x^k - g(x): schoolbook multiplication, then long division by f. Small fields
//    (q <= kTableLimit) are additionally tabulated in full (addition, multiplication, negation,
//    inversion); larger ones answer every query by the same polynomial arithmetic.
//  - Irreducibility of f by brute force: f has no monic factor of degree 1 .. k/2.
//  - The five arrays (Bose, Bush, Bose-Bush, Addelman-Kempthorne, full factorial) as N x c tables.
//  - isOrthogonalArray: exhaustive count of every level tuple on every t-subset of columns.
//
// Elements are encoded as integers in [0, q) whose base-p digits are the coefficients (digit i <->
// x^i); that is only a naming convention for the q elements, shared with the library so that the
// arrays can be compared entry by entry.
#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace textbook {

/// Polynomial over GF(p): coefficient i belongs to x^i; trimmed (no trailing zeros), so the zero
/// polynomial is empty.
using Poly = std::vector<int>;
/// N rows x c columns of levels.
using Array = std::vector<std::vector<int>>;

inline int modp(long long v, int p)
{
    const long long r = v % p;
    return int(r < 0 ? r + p : r);
}

inline void trim(Poly& a)
{
    while (!a.empty() && a.back() == 0) a.pop_back();
}

/// Degree; -1 for the zero polynomial.
inline int degree(const Poly& a)
{
    return int(a.size()) - 1;
}

inline Poly polyAdd(const Poly& a, const Poly& b, int p)
{
    Poly r(std::max(a.size(), b.size()), 0);
    for (std::size_t i = 0; i < r.size(); ++i) {
        const int x = i < a.size() ? a[i] : 0;
        const int y = i < b.size() ? b[i] : 0;
        r[i] = modp(x + y, p);
    }
    trim(r);
    return r;
}

inline Poly polyNeg(const Poly& a, int p)
{
    Poly r(a.size());
    for (std::size_t i = 0; i < a.size(); ++i) r[i] = modp(-a[i], p);
    trim(r);
    return r;
}

/// Schoolbook product.
inline Poly polyMul(const Poly& a, const Poly& b, int p)
{
    if (a.empty() || b.empty()) return {};
    Poly r(a.size() + b.size() - 1, 0);
    for (std::size_t i = 0; i < a.size(); ++i)
        for (std::size_t j = 0; j < b.size(); ++j) r[i + j] = modp(r[i + j] + (long long)a[i] * b[j], p);
    trim(r);
    return r;
}

/// Remainder of a modulo the monic polynomial m, by long division.
inline Poly polyRem(Poly a, const Poly& m, int p)
{
    if (m.empty() || m.back() != 1) throw std::logic_error("polyRem: divisor must be monic");
    trim(a);
    const int dm = degree(m);
    while (degree(a) >= dm) {
        const int shift = degree(a) - dm;
        const int lead = a.back();
        for (int i = 0; i <= dm; ++i) a[shift + i] = modp(a[shift + i] - (long long)lead * m[i], p);
        trim(a);  // the leading term cancels exactly since m is monic
    }
    return a;
}

/// The monic polynomial of degree d whose lower coefficients are the base-p digits of `index`
/// (index < p^d): enumerating index = 0 .. p^d - 1 lists every monic polynomial of degree d.
inline Poly monicPolynomial(int p, int d, long long index)
{
    Poly h(d + 1, 0);
    for (int i = 0; i < d; ++i) {
        h[i] = int(index % p);
        index /= p;
    }
    h[d] = 1;
    return h;
}

/// f(x) = x^k - g(x), g's k coefficients packed as the base-p digits of `g`.
inline Poly modulusFromPacked(int p, int k, std::uint32_t g)
{
    Poly f(k + 1, 0);
    for (int i = 0; i < k; ++i) {
        f[i] = modp(-int(g % std::uint32_t(p)), p);
        g /= std::uint32_t(p);
    }
    f[k] = 1;
    return f;
}

/// Brute force: a monic f of degree k >= 1 is irreducible over GF(p) iff no monic polynomial of
/// degree 1 .. floor(k/2) divides it (any factorisation has a factor of degree <= k/2).
inline bool isIrreducible(const Poly& f, int p)
{
    Poly g = f;
    trim(g);
    const int k = degree(g);
    if (k < 1 || g.back() != 1) return false;
    for (int d = 1; d <= k / 2; ++d) {
        long long count = 1;
        for (int i = 0; i < d; ++i) count *= p;
        for (long long index = 0; index < count; ++index)
            if (polyRem(g, monicPolynomial(p, d, index), p).empty()) return false;
    }
    return true;
}

/// GF(p)[x] / (f), f = x^k - g(x). A field when f is irreducible (check with isIrreducible);
/// otherwise just the quotient ring (add/mul/pow stay meaningful, inverses may not exist).
class Field {
public:
    static constexpr int kTableLimit = 256;

    Field(int p, int k, std::uint32_t packedG, bool buildTables = true)
        : p_(p), k_(k), q_(1), modulus_(modulusFromPacked(p, k, packedG))
    {
        for (int i = 0; i < k; ++i) q_ *= p;
        if (buildTables && q_ <= kTableLimit) build();
    }

    int p() const { return p_; }
    int k() const { return k_; }
    int q() const { return q_; }
    const Poly& modulus() const { return modulus_; }
    bool tabulated() const { return !mulTable_.empty(); }

    /// Element <-> polynomial (base-p digits <-> coefficients).
    Poly toPoly(int a) const
    {
        Poly r(k_, 0);
        for (int i = 0; i < k_; ++i) {
            r[i] = a % p_;
            a /= p_;
        }
        trim(r);
        return r;
    }
    int toInt(const Poly& a) const
    {
        int v = 0;
        for (int i = degree(a); i >= 0; --i) v = v * p_ + a[i];
        return v;
    }

    /// Arithmetic straight from the polynomial definitions (no tables).
    int addNaive(int a, int b) const { return toInt(polyAdd(toPoly(a), toPoly(b), p_)); }
    int negNaive(int a) const { return toInt(polyNeg(toPoly(a), p_)); }
    int mulNaive(int a, int b) const { return toInt(polyRem(polyMul(toPoly(a), toPoly(b), p_), modulus_, p_)); }

    /// Table lookups where tabulated, else the naive arithmetic.
    int add(int a, int b) const { return tabulated() ? addTable_[a * q_ + b] : addNaive(a, b); }
    int neg(int a) const { return tabulated() ? negTable_[a] : negNaive(a); }
    int sub(int a, int b) const { return add(a, neg(b)); }
    int mul(int a, int b) const { return tabulated() ? mulTable_[a * q_ + b] : mulNaive(a, b); }
    /// Multiplicative inverse by exhaustive search (tabulated fields: precomputed); -1 if none.
    int inv(int a) const
    {
        if (tabulated()) return invTable_[a];
        for (int b = 1; b < q_; ++b)
            if (mul(a, b) == 1) return b;
        return -1;
    }
    int div(int a, int b) const { return mul(a, inv(b)); }
    /// a^e by square-and-multiply (a^0 = 1).
    int pow(int a, std::uint64_t e) const
    {
        int result = 1, base = a;
        while (e != 0) {
            if (e & 1u) result = mul(result, base);
            base = mul(base, base);
            e >>= 1;
        }
        return result;
    }
    /// The element n * 1 = 1 + 1 + ... + 1 (n terms).
    int fromInt(int n) const
    {
        int r = 0;
        for (int i = 0; i < n; ++i) r = add(r, 1);
        return r;
    }
    /// The class of the polynomial x (for k >= 2 its integer code is p; for k = 1 it is g(0)).
    int x() const { return toInt(polyRem(Poly{0, 1}, modulus_, p_)); }

    /// Smallest nonzero element that is not a square (q odd).
    int smallestNonSquare() const
    {
        std::vector<char> square(q_, 0);
        for (int a = 0; a < q_; ++a) square[mul(a, a)] = 1;
        for (int a = 1; a < q_; ++a)
            if (!square[a]) return a;
        return -1;
    }

private:
    void build()
    {
        const int q = q_;
        addTable_.assign(std::size_t(q) * q, 0);
        mulTable_.assign(std::size_t(q) * q, 0);
        negTable_.assign(q, 0);
        invTable_.assign(q, -1);
        for (int a = 0; a < q; ++a) {
            negTable_[a] = negNaive(a);
            for (int b = 0; b < q; ++b) {
                addTable_[a * q + b] = addNaive(a, b);
                mulTable_[a * q + b] = mulNaive(a, b);
            }
        }
        for (int a = 1; a < q; ++a)
            for (int b = 1; b < q; ++b)
                if (mulTable_[a * q + b] == 1) {
                    invTable_[a] = b;
                    break;
                }
    }

    int p_, k_, q_;
    Poly modulus_;
    std::vector<int> addTable_, mulTable_, negTable_, invTable_;
};

/// Bose 1938, OA(q^2, q+1, q, 2): row (a, b) in GF(q)^2 at index a*q + b; columns a, b and
/// a + lambda*b for the q-1 nonzero lambda (column 1 + lambda, lambda's integer code).
inline Array bose(const Field& F)
{
    const int q = F.q();
    Array A;
    for (int a = 0; a < q; ++a)
        for (int b = 0; b < q; ++b) {
            std::vector<int> row = {a, b};
            for (int lambda = 1; lambda < q; ++lambda) row.push_back(F.add(a, F.mul(lambda, b)));
            A.push_back(row);
        }
    return A;
}

/// Bush 1952, OA(q^t, q+1, q, t), t <= q: one row per polynomial phi(x) = c_0 + c_1 x + ... +
/// c_{t-1} x^{t-1} over GF(q) (row index sum c_i q^i); column e (an element) is phi(e), column q
/// (the point at infinity) is the leading coefficient c_{t-1}.
inline Array bush(const Field& F, int t)
{
    const int q = F.q();
    long long n = 1;
    for (int i = 0; i < t; ++i) n *= q;
    Array A;
    for (long long r = 0; r < n; ++r) {
        std::vector<int> c(t);
        long long v = r;
        for (int i = 0; i < t; ++i) {
            c[i] = int(v % q);
            v /= q;
        }
        std::vector<int> row;
        for (int e = 0; e < q; ++e) {
            int value = 0;
            for (int i = 0; i < t; ++i) value = F.add(value, F.mul(c[i], F.pow(e, std::uint64_t(i))));
            row.push_back(value);
        }
        row.push_back(c[t - 1]);
        A.push_back(row);
    }
    return A;
}

/// The Bose-Bush difference scheme D(2q, 2q, q) over the additive group of GF(2)^m (q = 2^m):
/// D[i][j] = phi(i * j), the multiplication table of F = GF(2q) pushed through the additive
/// surjection phi: F -> GF(2)^m that drops the coefficient of x^m (the top bit of the code).
inline Array boseBushDifferenceScheme(const Field& F2q)
{
    const int n = F2q.q(), q = n / 2;
    Array D(n, std::vector<int>(n));
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) D[i][j] = F2q.mul(i, j) % q;  // phi: keep the low m digits
    return D;
}

/// Bose and Bush 1952, OA(2q^2, 2q+1, q, 2), q = 2^m: the difference scheme developed over the
/// group (row (i, g) at index i*q + g: D[i][j] + g, + being XOR in GF(2)^m), plus one column
/// constant on each D-row that takes every level on exactly two D-rows (here floor(i/2)).
inline Array boseBush(const Field& F2q)
{
    const int n = F2q.q(), q = n / 2;
    const Array D = boseBushDifferenceScheme(F2q);
    Array A;
    for (int i = 0; i < n; ++i)
        for (int g = 0; g < q; ++g) {
            std::vector<int> row;
            for (int j = 0; j < n; ++j) row.push_back(D[i][j] ^ g);
            row.push_back(i / 2);
            A.push_back(row);
        }
    return A;
}

/// Addelman and Kempthorne 1961, OA(2q^2, 2q+1, q, 2), q odd, with a non-square k of GF(q). Row
/// (h, i, j) at index h*q^2 + i*q + j. Half h = 0: columns j; i + m j (m in GF(q));
/// i^2 + m i + j. Half h = 1: j; i + m j + b_m; k i^2 + k m i + j + c_m, where b_0 = 0,
/// b_m = (k - 1) / (4 k m) for m != 0, and c_m = m^2 (k - 1) / 4.
inline Array addelmanKempthorne(const Field& F, int k)
{
    const int q = F.q();
    const int four = F.fromInt(4);
    const int kMinus1 = F.sub(k, 1);
    Array A;
    for (int h = 0; h < 2; ++h)
        for (int i = 0; i < q; ++i)
            for (int j = 0; j < q; ++j) {
                std::vector<int> row = {j};
                for (int m = 0; m < q; ++m) {
                    int v = F.add(i, F.mul(m, j));
                    if (h == 1 && m != 0) v = F.add(v, F.div(kMinus1, F.mul(four, F.mul(k, m))));
                    row.push_back(v);
                }
                for (int m = 0; m < q; ++m) {
                    const int ii = F.mul(i, i), mi = F.mul(m, i);
                    int v;
                    if (h == 0) {
                        v = F.add(F.add(ii, mi), j);
                    } else {
                        const int cm = F.div(F.mul(F.mul(m, m), kMinus1), four);
                        v = F.add(F.add(F.add(F.mul(k, ii), F.mul(k, mi)), j), cm);
                    }
                    row.push_back(v);
                }
                A.push_back(row);
            }
    return A;
}

/// The full factorial OA(s^d, d, s, d): column j of row r is base-s digit j of r.
inline Array fullFactorial(int s, int d)
{
    long long n = 1;
    for (int i = 0; i < d; ++i) n *= s;
    Array A;
    for (long long r = 0; r < n; ++r) {
        std::vector<int> row;
        long long v = r;
        for (int j = 0; j < d; ++j) {
            row.push_back(int(v % s));
            v /= s;
        }
        A.push_back(row);
    }
    return A;
}

/// Calls visit(subset) for every t-subset of `cols` (lexicographic); stops early when it returns
/// false. Returns false iff stopped.
template <class Visit>
bool forEachSubset(const std::vector<int>& cols, int t, Visit&& visit)
{
    const int c = int(cols.size());
    if (t > c || t < 0) return true;
    std::vector<int> idx(t);
    for (int i = 0; i < t; ++i) idx[i] = i;
    std::vector<int> subset(t);
    while (true) {
        for (int i = 0; i < t; ++i) subset[i] = cols[idx[i]];
        if (!visit(subset)) return false;
        int i = t - 1;
        while (i >= 0 && idx[i] == c - t + i) --i;
        if (i < 0) return true;
        ++idx[i];
        for (int j = i + 1; j < t; ++j) idx[j] = idx[j - 1] + 1;
    }
}

/// True iff, for every t-subset of the columns `cols`, each of the s^t level tuples occurs in
/// exactly N / s^t rows (all entries of those columns must lie in [0, s); N must be a multiple
/// of s^t, otherwise no array with N rows can be of strength t). Exhaustive over all subsets.
/// On failure `why` (when given) names the first offending subset.
inline bool isOrthogonalArray(const Array& A, int s, int t, std::vector<int> cols, std::string* why = nullptr)
{
    auto fail = [&](const std::string& reason) {
        if (why) *why = reason;
        return false;
    };
    const long long n = (long long)A.size();
    long long cells = 1;
    for (int i = 0; i < t; ++i) cells *= s;
    if (t < 1 || s < 1 || int(cols.size()) < t) return fail("need 1 <= t <= number of columns");
    if (n == 0 || n % cells != 0) return fail("N = " + std::to_string(n) + " is not a multiple of s^t");
    const long long lambda = n / cells;
    for (long long r = 0; r < n; ++r)
        for (int c : cols) {
            if (c < 0 || c >= int(A[r].size())) return fail("column " + std::to_string(c) + " missing");
            if (A[r][c] < 0 || A[r][c] >= s)
                return fail("entry (" + std::to_string(r) + ", " + std::to_string(c) + ") = " + std::to_string(A[r][c]) +
                            " is not a level in [0, s)");
        }
    std::vector<long long> count(cells);
    std::string reason;
    const bool ok = forEachSubset(cols, t, [&](const std::vector<int>& subset) {
        std::fill(count.begin(), count.end(), 0);
        for (long long r = 0; r < n; ++r) {
            long long cell = 0;
            for (int c : subset) cell = cell * s + A[r][c];
            ++count[cell];
        }
        for (long long cell = 0; cell < cells; ++cell)
            if (count[cell] != lambda) {
                reason = "columns {";
                for (std::size_t i = 0; i < subset.size(); ++i) reason += (i ? "," : "") + std::to_string(subset[i]);
                reason += "}: level tuple #" + std::to_string(cell) + " occurs " + std::to_string(count[cell]) +
                          " times, expected " + std::to_string(lambda);
                return false;
            }
        return true;
    });
    return ok ? true : fail(reason);
}

/// All columns 0 .. c-1.
inline std::vector<int> allColumns(int c)
{
    std::vector<int> cols(c);
    for (int i = 0; i < c; ++i) cols[i] = i;
    return cols;
}

}  // namespace textbook
