// Validation, construction parameters and the OA chooser. Field constants (a primitive
// polynomial per GF(p^k), a non-square for Addelman-Kempthorne) are found here once per pattern
// with the same GLSL field code the shaders run, so the host and shaders agree by construction.
#include "oas/pattern.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "oas/glsl_compat.hpp"

namespace oas {
namespace {

using glsl::OasField;

bool isPrime(std::uint32_t n)
{
    if (n < 2) return false;
    for (std::uint32_t d = 2; d * d <= n; ++d)
        if (n % d == 0) return false;
    return true;
}

OasField makeField(std::uint32_t p, std::uint32_t k, std::uint32_t poly)
{
    OasField f;
    const Divisor byP = makeDivisor(p);
    f.recipP = byP.recip;
    f.shiftP = byP.shift;
    f.p = p;
    f.k = k;
    f.q = 1;
    for (std::uint32_t i = 0; i < k; ++i) f.q *= p;
    f.poly = poly;
    return f;
}

/// Integer power, or 0 when the result would exceed `limit`.
std::uint32_t powCapped(std::uint32_t base, std::uint32_t exponent, std::uint32_t limit)
{
    std::uint64_t v = 1;
    for (std::uint32_t i = 0; i < exponent; ++i) {
        v *= base;
        if (v > limit) return 0;
    }
    return std::uint32_t(v);
}

std::uint32_t offsetCode(const std::string& offset)
{
    if (offset == "centered") return glsl::OAS_OFFSET_CENTERED;
    if (offset == "j") return glsl::OAS_OFFSET_J;
    if (offset == "mj") return glsl::OAS_OFFSET_MJ;
    if (offset == "cmj") return glsl::OAS_OFFSET_CMJ;
    throw InvalidArgument("offset '" + offset + "' is not valid: use centered, j, mj or cmj");
}

std::string offsetName(std::uint32_t code)
{
    static const char* names[] = {"centered", "j", "mj", "cmj"};
    return code < 4 ? names[code] : "?";
}

struct SamplerInfo {
    std::uint32_t code;
    const char* description;
};

const std::map<std::string, SamplerInfo>& samplerTable()
{
    static const std::map<std::string, SamplerInfo> table = {
        {"bose", {glsl::OAS_BOSE, "Bose OA(q^2, q+1, q, 2), q prime power <= 4096: N = 4, 9, 16, 25, 49, 64, 81, 121 ..."}},
        {"bush", {glsl::OAS_BUSH, "Bush OA(q^t, q+1, q, t), q prime power >= t: strength t"}},
        {"bose-bush", {glsl::OAS_BOSE_BUSH, "Bose-Bush OA(2q^2, 2q+1, q, 2), q = 2^k: N = 8, 32, 128, 512, 2048 ..."}},
        {"addelman-kempthorne", {glsl::OAS_ADDELMAN_KEMPTHORNE, "Addelman-Kempthorne OA(2q^2, 2q+1, q, 2), q odd prime power: N = 18, 50, 98, 162 ..."}},
        {"cmjnd", {glsl::OAS_CMJND, "CMJND OA(s^d, d, s, d): full factorial, any s >= 2, strength d"}},
        {"random", {glsl::OAS_RANDOM, "independent uniform random (baseline)"}},
        {"jittered2d", {glsl::OAS_JITTERED_2D, "jittered nx*ny grid per dimension pair, padded (baseline)"}},
        {"cmj2d", {glsl::OAS_CMJ_2D, "correlated multi-jittered 2D per pair, padded (Kensler 2013; baseline)"}},
        {"zerotwo", {glsl::OAS_ZERO_TWO, "Owen-scrambled (0,2)-sequence per pair, padded (baseline)"}},
        {"halton", {glsl::OAS_HALTON, "Halton with random digit permutations, blocks of 32 dims (baseline)"}},
        {"sobol", {glsl::OAS_SOBOL, "Owen-scrambled Sobol, blocks of 64 dims (baseline; our direction numbers)"}},
    };
    return table;
}

const SamplerInfo& samplerInfo(const std::string& name)
{
    auto it = samplerTable().find(name);
    if (it == samplerTable().end()) {
        std::string list = "oa";
        for (auto& n : samplerNames()) list += ", " + n;
        throw InvalidArgument("sampler '" + name + "' is unknown: valid samplers are " + list);
    }
    return it->second;
}

std::uint32_t defaultStrength(std::uint32_t code, std::uint32_t dims)
{
    if (code == glsl::OAS_CMJND) return std::max<std::uint32_t>(dims, 1);
    return 2;
}

/// The exact pattern for (sampler, spp, strength), or an empty optional-like Pattern (N = 0)
/// with `why` set when spp cannot be made exactly.
Pattern exactPatternFields(std::uint32_t code, std::uint32_t spp, std::uint32_t t, std::uint32_t offset,
                           std::string& why);

/// exactPattern plus the derived constants every shader divides by.
Pattern exactPattern(std::uint32_t code, std::uint32_t spp, std::uint32_t t, std::uint32_t offset, std::string& why)
{
    Pattern pat = exactPatternFields(code, spp, t, offset, why);
    if (pat.N == 0) return pat;
    if (code < glsl::OAS_RANDOM) pat.aux2 = pat.N / pat.s;
    const Divisor s = makeDivisor(pat.s), p = makeDivisor(std::max<std::uint32_t>(pat.fieldP, 1)),
                  n = makeDivisor(pat.N);
    pat.recipS = s.recip;
    pat.recipP = p.recip;
    pat.recipN = n.recip;
    pat.recipShifts = s.shift | (p.shift << 8) | (n.shift << 16);
    return pat;
}

Pattern exactPatternFields(std::uint32_t code, std::uint32_t spp, std::uint32_t t, std::uint32_t offset,
                           std::string& why)
{
    Pattern pat;
    pat.construction = code;
    pat.N = spp;
    pat.strength = t;
    pat.offset = code < glsl::OAS_RANDOM ? offset : 0;
    auto fail = [&](const std::string& reason) {
        why = reason;
        return Pattern{};
    };
    auto setField = [&](std::uint32_t q) {
        const PrimePower pk = primePower(q);
        pat.fieldP = pk.p;
        pat.fieldK = pk.k;
        pat.fieldQ = q;
        pat.fieldPoly = pk.k > 1 ? primitivePolynomial(pk.p, pk.k) : 0;
    };
    switch (code) {
    case glsl::OAS_BOSE: {
        if (t != 2) return fail("bose has strength 2 only");
        const auto q = std::uint32_t(std::lround(std::sqrt(double(spp))));
        if (q * q != spp) return fail(std::to_string(spp) + " is not a square q^2");
        if (primePower(q).p == 0) return fail("q = " + std::to_string(q) + " is not a prime power");
        if (q > kMaxBoseQ) return fail("q = " + std::to_string(q) + " exceeds 4096");
        pat.s = q;
        pat.blockDims = q + 1;
        setField(q);
        return pat;
    }
    case glsl::OAS_BUSH: {
        if (t < 2) return fail("bush needs strength t >= 2");
        const auto q = std::uint32_t(std::lround(std::pow(double(spp), 1.0 / t)));
        if (q < 2 || powCapped(q, t, kMaxSamples) != spp)
            return fail(std::to_string(spp) + " is not q^" + std::to_string(t));
        if (primePower(q).p == 0) return fail("q = " + std::to_string(q) + " is not a prime power");
        if (q < t) return fail("bush needs q >= t (q = " + std::to_string(q) + ", t = " + std::to_string(t) + ")");
        pat.s = q;
        pat.blockDims = q + 1;
        pat.aux = spp / q;  // q^(t-1)
        setField(q);
        return pat;
    }
    case glsl::OAS_BOSE_BUSH:
    case glsl::OAS_ADDELMAN_KEMPTHORNE: {
        const bool bb = code == glsl::OAS_BOSE_BUSH;
        const char* name = bb ? "bose-bush" : "addelman-kempthorne";
        if (t != 2) return fail(std::string(name) + " has strength 2 only");
        const auto q = std::uint32_t(std::lround(std::sqrt(double(spp) / 2)));
        if (spp % 2 != 0 || 2 * q * q != spp) return fail(std::to_string(spp) + " is not 2q^2");
        const PrimePower pk = primePower(q);
        if (bb && pk.p != 2) return fail("q = " + std::to_string(q) + " is not a power of two");
        if (!bb && (pk.p == 0 || pk.p == 2)) return fail("q = " + std::to_string(q) + " is not an odd prime power");
        pat.s = q;
        pat.blockDims = 2 * q + 1;
        if (bb) {
            setField(2 * q);  // GF(2q), mapped onto q levels by dropping the top bit
        } else {
            setField(q);
            const OasField f = makeField(pat.fieldP, pat.fieldK, pat.fieldPoly);
            for (std::uint32_t a = 1; a < q; ++a)
                if (glsl::oas_gf_pow(f, a, (q - 1) / 2) != 1) { pat.aux = a; break; }
        }
        return pat;
    }
    case glsl::OAS_CMJND: {
        if (t < 1) return fail("cmjnd needs d >= 1 dimensions");
        const auto s = std::uint32_t(std::lround(std::pow(double(spp), 1.0 / t)));
        if (s < 2 || powCapped(s, t, kMaxSamples) != spp)
            return fail(std::to_string(spp) + " is not s^" + std::to_string(t) + " with s >= 2");
        pat.s = s;
        pat.blockDims = t;
        return pat;
    }
    default: {  // baselines take any N
        pat.s = spp;
        pat.blockDims = code == glsl::OAS_HALTON ? glsl::OAS_HALTON_BLOCK
                        : code == glsl::OAS_SOBOL ? glsl::OAS_SOBOL_BLOCK
                        : code == glsl::OAS_RANDOM ? 1 : 2;
        pat.strength = code == glsl::OAS_RANDOM ? 0 : (code == glsl::OAS_HALTON || code == glsl::OAS_SOBOL ? 1 : 2);
        // Grid nx * ny = N with nx the largest divisor <= sqrt(N) (squares give n x n).
        std::uint32_t nx = std::uint32_t(std::sqrt(double(spp)));
        while (nx > 1 && spp % nx != 0) --nx;
        pat.aux = std::max<std::uint32_t>(nx, 1);
        pat.aux2 = spp / pat.aux;
        return pat;
    }
    }
}

std::string countList(const std::vector<std::uint32_t>& counts)
{
    std::string out;
    for (auto c : counts) out += (out.empty() ? "" : ", ") + std::to_string(c);
    return out.empty() ? "none" : out;
}

/// Nearest valid counts below and above spp (either may be missing).
std::vector<std::uint32_t> nearestCounts(const std::string& sampler, std::uint32_t t, std::uint32_t dims,
                                         std::uint32_t spp)
{
    std::vector<std::uint32_t> all = validCounts(sampler, t, dims, 1, kMaxSamples);
    std::vector<std::uint32_t> near;
    auto above = std::lower_bound(all.begin(), all.end(), spp);
    if (above != all.begin()) near.push_back(*(above - 1));
    if (above != all.end()) near.push_back(*above);
    return near;
}

void checkCommon(const PatternRequest& r)
{
    if (r.spp < 1 || r.spp > kMaxSamples)
        throw InvalidArgument("spp " + std::to_string(r.spp) + " is out of range: valid 1 .. " +
                              std::to_string(kMaxSamples));
    if (r.dims < 1 || r.dims > kMaxDims)
        throw InvalidArgument("dims " + std::to_string(r.dims) + " is out of range: valid 1 .. " +
                              std::to_string(kMaxDims));
    if (r.strength > 24)
        throw InvalidArgument("strength " + std::to_string(r.strength) + " is out of range: valid 2 .. 24");
}

}  // namespace

const std::vector<std::uint32_t>& sobolDirections()
{
    static const std::vector<std::uint32_t> table = [] {
        const std::uint32_t dims = glsl::OAS_SOBOL_BLOCK;
        std::vector<std::uint32_t> v(dims * 32, 0);
        for (std::uint32_t b = 0; b < 32; ++b) v[b] = 1u << (31 - b);  // van der Corput
        // Primitive polynomials over GF(2) in order of degree, then value: x^k + g(x) with x of
        // order 2^k - 1 (the GF(2^k) test primitivePolynomial uses), every g, not just the first.
        std::uint32_t dim = 1;
        for (std::uint32_t degree = 1; dim < dims; ++degree) {
            for (std::uint32_t g = 1; g < (1u << degree) && dim < dims; g += 2) {
                if (degree > 1) {
                    const OasField f = makeField(2, degree, g);
                    std::uint32_t power = 1, order = 0;
                    do {
                        power = glsl::oas_gf_mulx(f, power);
                        ++order;
                    } while (power != 1 && order < f.q - 1);
                    if (!(power == 1 && order == f.q - 1)) continue;
                }
                // m_1..m_degree odd, m_k < 2^k; dimension 1 (x + 1) keeps m_1 = 1.
                std::vector<std::uint32_t> m(33, 0);
                for (std::uint32_t k = 1; k <= degree; ++k)
                    m[k] = dim == 1 ? 1u : ((glsl::oas_pcg(dim * 64 + k) & ((1u << k) - 1)) | 1u);
                // Bratley and Fox (1988): m_k = 2 a_1 m_{k-1} ^ 4 a_2 m_{k-2} ^ ... ^ 2^s m_{k-s} ^ m_{k-s},
                // with g's bits a_{s-1} .. a_1 the inner coefficients and a_s = 1.
                for (std::uint32_t k = degree + 1; k <= 32; ++k) {
                    std::uint32_t mk = m[k - degree] ^ (m[k - degree] << degree);
                    for (std::uint32_t i = 1; i < degree; ++i)
                        if ((g >> (degree - i)) & 1u) mk ^= m[k - i] << i;
                    m[k] = mk;
                }
                for (std::uint32_t b = 0; b < 32; ++b) v[dim * 32 + b] = m[b + 1] << (31 - b);
                ++dim;
            }
        }
        return v;
    }();
    return table;
}

Divisor makeDivisor(std::uint32_t d)
{
    if (d == 0) throw std::invalid_argument("makeDivisor: division by zero");
    std::uint32_t l = 0;
    while ((std::uint64_t(1) << l) < d) ++l;  // ceil(log2 d)
    const std::uint64_t recip = ((std::uint64_t(1) << 32) * ((std::uint64_t(1) << l) - d)) / d + 1;
    return {std::uint32_t(recip), l};
}

const std::vector<std::string>& samplerNames()
{
    static const std::vector<std::string> names = {"bose", "bush", "bose-bush", "addelman-kempthorne", "cmjnd",
                                                   "random", "jittered2d", "cmj2d", "zerotwo", "halton", "sobol"};
    return names;
}

std::string samplerDescription(const std::string& name)
{
    if (name == "oa") return "the best orthogonal array for (spp, dims, strength), chosen and explained";
    return samplerInfo(name).description;
}

bool isOrthogonalArray(const std::string& name)
{
    return name == "oa" || samplerInfo(name).code < glsl::OAS_RANDOM;
}

std::string constructionName(std::uint32_t construction)
{
    for (auto& [name, info] : samplerTable())
        if (info.code == construction) return name;
    return "unknown(" + std::to_string(construction) + ")";
}

PrimePower primePower(std::uint32_t q)
{
    if (q < 2) return {};
    std::uint32_t p = 2;
    while (q % p != 0) ++p;  // smallest prime factor
    std::uint32_t k = 0;
    std::uint32_t v = q;
    while (v % p == 0) { v /= p; ++k; }
    return v == 1 ? PrimePower{p, k} : PrimePower{};
}

std::uint32_t primitivePolynomial(std::uint32_t p, std::uint32_t k)
{
    const OasField probe = makeField(p, k, 0);
    if (!isPrime(p) || k < 1 || probe.q > kMaxFieldQ + 1 || probe.q < 2)
        throw InvalidArgument("GF(" + std::to_string(p) + "^" + std::to_string(k) + ") is not supported: need p prime and p^k <= 65536");
    if (k == 1) return 0;
    static std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> cache;
    if (auto it = cache.find({p, k}); it != cache.end()) return it->second;
    // x has order q-1 only if f is irreducible (a reducible f leaves fewer than q-1 units), so
    // the first g passing the order test gives a field, and x generates its multiplicative group.
    for (std::uint32_t g = 1; g < probe.q; ++g) {
        if (g % p == 0) continue;  // f(0) = -g(0) must be nonzero
        const OasField f = makeField(p, k, g);
        std::uint32_t power = 1;
        std::uint32_t order = 0;
        do {
            power = glsl::oas_gf_mulx(f, power);
            ++order;
        } while (power != 1 && order < f.q - 1);
        if (power == 1 && order == f.q - 1) {
            cache[{p, k}] = g;
            return g;
        }
    }
    throw std::logic_error("no primitive polynomial found for GF(p^k)");  // cannot happen
}

std::vector<std::uint32_t> validCounts(const std::string& sampler, std::uint32_t strength, std::uint32_t dims,
                                       std::uint32_t lo, std::uint32_t hi)
{
    std::vector<std::uint32_t> out;
    if (sampler == "oa") {
        for (auto& name : samplerNames()) {
            if (!isOrthogonalArray(name)) continue;
            const std::uint32_t t = strength ? strength : 2;
            if (name == "cmjnd") {
                for (std::uint32_t d = t; d <= std::max(t, dims); ++d)
                    for (auto c : validCounts(name, d, d, lo, hi)) out.push_back(c);
            } else if (name == "bush" || t == 2) {
                for (auto c : validCounts(name, t, dims, lo, hi)) out.push_back(c);
            }
        }
        std::sort(out.begin(), out.end());
        out.erase(std::unique(out.begin(), out.end()), out.end());
        return out;
    }
    const SamplerInfo& info = samplerInfo(sampler);
    const std::uint32_t t = strength ? strength : defaultStrength(info.code, dims);
    hi = std::min(hi, kMaxSamples);
    auto consider = [&](std::uint64_t n) {
        if (n < lo || n > hi) return;
        std::string why;
        if (exactPattern(info.code, std::uint32_t(n), t, 0, why).N != 0) out.push_back(std::uint32_t(n));
    };
    switch (info.code) {
    case glsl::OAS_BOSE:
    case glsl::OAS_BOSE_BUSH:
    case glsl::OAS_ADDELMAN_KEMPTHORNE:
        for (std::uint64_t q = 2; q <= 4096; ++q) consider(info.code == glsl::OAS_BOSE ? q * q : 2 * q * q);
        break;
    case glsl::OAS_BUSH:
    case glsl::OAS_CMJND:
        for (std::uint32_t q = 2; q <= kMaxSamples; ++q) {
            const std::uint32_t n = powCapped(q, t, kMaxSamples);
            if (n == 0) break;
            consider(n);
        }
        break;
    default:
        for (std::uint64_t n = lo; n <= hi && out.size() < 64; ++n) consider(n);
    }
    std::sort(out.begin(), out.end());
    return out;
}

Pattern makePattern(const PatternRequest& request)
{
    checkCommon(request);
    if (request.sampler == "oa") return chooseOrthogonalArray(request).pattern;
    const SamplerInfo& info = samplerInfo(request.sampler);
    const std::uint32_t offset = offsetCode(request.offset);
    const std::uint32_t t = request.strength ? request.strength : defaultStrength(info.code, request.dims);
    if (info.code == glsl::OAS_CMJND && request.strength == 0 && request.dims > 24)
        throw InvalidArgument("cmjnd: dims " + std::to_string(request.dims) +
                              " is too many for one full factorial (s^d <= 2^24 needs d <= 24); pass --strength d to pad with blocks of d dims");
    const bool strengthTwoOnly = info.code == glsl::OAS_BOSE || info.code == glsl::OAS_BOSE_BUSH ||
                                 info.code == glsl::OAS_ADDELMAN_KEMPTHORNE;
    if (strengthTwoOnly && t != 2)
        throw InvalidArgument("sampler '" + request.sampler + "' has strength 2 only (strength " + std::to_string(t) +
                              " asked): use bush or cmjnd for strength 3 and more");
    std::string why;
    Pattern pat = exactPattern(info.code, request.spp, t, offset, why);
    if (pat.N != 0) return pat;
    const auto near = nearestCounts(request.sampler, t, request.dims, request.spp);
    if (request.roundUp && !near.empty() && near.back() > request.spp)
        return exactPattern(info.code, near.back(), t, offset, why);
    throw InvalidArgument("sampler '" + request.sampler + "' (strength " + std::to_string(t) +
                          ") cannot make exactly spp " + std::to_string(request.spp) + ": " + why +
                          "; nearest valid spp: " + countList(near) +
                          (near.empty() ? "" : " (or allow rounding up)"));
}

Choice chooseOrthogonalArray(const PatternRequest& request)
{
    checkCommon(request);
    const std::uint32_t t = request.strength ? request.strength : 2;
    const std::uint32_t offset = offsetCode(request.offset);
    struct Candidate {
        std::string name;
        Pattern pat;
    };
    auto candidatesFor = [&](std::uint32_t spp) {
        std::vector<Candidate> found;
        for (auto& name : samplerNames()) {
            const std::uint32_t code = samplerInfo(name).code;
            if (code >= glsl::OAS_RANDOM) continue;
            std::vector<std::uint32_t> strengths;
            if (code == glsl::OAS_BUSH || code == glsl::OAS_CMJND)
                for (std::uint32_t s = t; s <= std::max(t, std::min<std::uint32_t>(request.dims, 24)); ++s)
                    strengths.push_back(s);
            else if (t == 2)
                strengths.push_back(2);
            for (auto s : strengths) {
                std::string why;
                Pattern pat = exactPattern(code, spp, s, offset, why);
                if (pat.N != 0) found.push_back({name, pat});
            }
        }
        return found;
    };
    std::uint32_t spp = request.spp;
    std::vector<Candidate> candidates = candidatesFor(spp);
    std::string note;
    if (candidates.empty()) {
        const auto near = nearestCounts("oa", t, request.dims, spp);
        if (!request.roundUp || near.empty() || near.back() <= spp)
            throw InvalidArgument("no orthogonal array of strength " + std::to_string(t) + " has exactly spp " +
                                  std::to_string(spp) + "; nearest valid spp: " + countList(near) +
                                  (near.empty() ? "" : " (or allow rounding up)"));
        note = "spp " + std::to_string(spp) + " rounded up to " + std::to_string(near.back()) + " as asked. ";
        spp = near.back();
        candidates = candidatesFor(spp);
    }
    // Ranking, most important first: the lowest strength that meets the request (more levels per
    // dimension, so finer t-D strata); one block covering all dims (or the most dims per block);
    // lambda = 1 (Bose, Bush) before lambda = 2 designs; the cheaper construction.
    auto key = [&](const Candidate& c) {
        const std::uint32_t covered = std::min(c.pat.blockDims, request.dims);
        const bool lambdaOne = c.pat.construction == glsl::OAS_BOSE || c.pat.construction == glsl::OAS_BUSH;
        return std::make_tuple(c.pat.strength, -std::int64_t(covered), lambdaOne ? 0 : 1, c.pat.construction);
    };
    std::stable_sort(candidates.begin(), candidates.end(),
                     [&](const Candidate& a, const Candidate& b) { return key(a) < key(b); });
    const Candidate& best = candidates.front();
    std::ostringstream why;
    why << note << "chose " << describe(best.pat) << " for spp " << spp << ", " << request.dims
        << " dims, strength >= " << t << ": ";
    const std::uint32_t blocks = (request.dims + best.pat.blockDims - 1) / best.pat.blockDims;
    why << (blocks == 1 ? "one OA block covers every dimension" : std::to_string(blocks) + " independently randomized OA blocks")
        << ", every " << best.pat.strength << "-D projection within a block stratified into " << best.pat.s
        << "^" << best.pat.strength << " cells";
    if (candidates.size() > 1) {
        why << "; other candidates:";
        for (std::size_t i = 1; i < candidates.size(); ++i) why << " [" << describe(candidates[i].pat) << "]";
    }
    return {best.pat, best.name, why.str()};
}

std::string describe(const Pattern& p)
{
    std::ostringstream out;
    out << constructionName(p.construction);
    if (p.construction < glsl::OAS_RANDOM) {
        out << " q=" << p.s << " N=" << p.N << " t=" << p.strength << " " << offsetName(p.offset) << ", "
            << p.blockDims << " dims/block";
        if (p.fieldK > 1) out << ", GF(" << p.fieldP << "^" << p.fieldK << ")";
    } else {
        out << " N=" << p.N;
        if (p.construction == glsl::OAS_JITTERED_2D || p.construction == glsl::OAS_CMJ_2D)
            out << " grid " << p.aux << "x" << p.aux2;
    }
    return out.str();
}

std::uint32_t pixelSeed(std::uint32_t x, std::uint32_t y, std::uint32_t seed) { return glsl::oas_pixel_seed(x, y, seed); }

}  // namespace oas
