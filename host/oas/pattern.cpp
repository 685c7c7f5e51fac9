// The C++ API over the C pattern builder (oas_pattern.c, which makes every value choice): names,
// validation messages with the nearest valid counts, and the OA chooser.
#include "oas/pattern.hpp"

#include <algorithm>
#include <cstring>
#include <map>
#include <sstream>

#include "oas/oas_pattern.h"

namespace oas {
namespace {

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
    if (offset == "centered") return OAS_OFFSET_CENTERED;
    if (offset == "j") return OAS_OFFSET_J;
    if (offset == "mj") return OAS_OFFSET_MJ;
    if (offset == "cmj") return OAS_OFFSET_CMJ;
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
        {"bose", {OAS_BOSE, "Bose OA(q^2, q+1, q, 2), q prime power <= 4096: N = 4, 9, 16, 25, 49, 64, 81, 121 ..."}},
        {"bush", {OAS_BUSH, "Bush OA(q^t, q+1, q, t), q prime power >= t: strength t"}},
        {"bose-bush", {OAS_BOSE_BUSH, "Bose-Bush OA(2q^2, 2q+1, q, 2), q = 2^k: N = 8, 32, 128, 512, 2048 ..."}},
        {"addelman-kempthorne", {OAS_ADDELMAN_KEMPTHORNE, "Addelman-Kempthorne OA(2q^2, 2q+1, q, 2), q odd prime power: N = 18, 50, 98, 162 ..."}},
        {"cmjnd", {OAS_CMJND, "CMJND OA(s^d, d, s, d): full factorial, any s >= 2, strength d"}},
        {"random", {OAS_RANDOM, "independent uniform random (baseline)"}},
        {"jittered2d", {OAS_JITTERED_2D, "jittered nx*ny grid per dimension pair, padded (baseline)"}},
        {"cmj2d", {OAS_CMJ_2D, "correlated multi-jittered 2D per pair, padded (Kensler 2013; baseline)"}},
        {"zerotwo", {OAS_ZERO_TWO, "Owen-scrambled (0,2)-sequence per pair, padded (baseline)"}},
        {"halton", {OAS_HALTON, "Halton with random digit permutations, blocks of 32 dims (baseline)"}},
        {"sobol", {OAS_SOBOL, "Owen-scrambled Sobol, blocks of 1024 dims (baseline; Joe-Kuo direction numbers)"}},
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
    if (code == OAS_CMJND) return std::max<std::uint32_t>(dims, 1);
    return 2;
}

/// The exact pattern for (construction, spp, strength t, offset) from the C builder
/// (oas_pattern.c, the one implementation of every value choice), or a Pattern with N = 0 and
/// `why` set when spp cannot be made exactly.
Pattern exactPattern(std::uint32_t code, std::uint32_t spp, std::uint32_t t, std::uint32_t offset, std::string& why)
{
    OasPattern built;
    char reason[256];
    if (oas_make_pattern(code, spp, t, offset, &built, reason, sizeof reason) != OAS_PATTERN_OK) {
        why = reason;
        return Pattern{};
    }
    Pattern pat;
    std::memcpy(static_cast<void*>(&pat), &built, sizeof pat);  // same 16 words
    return pat;
}
static_assert(sizeof(OasPattern) == sizeof(Pattern), "oas::Pattern mirrors the C OasPattern");

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
        std::vector<std::uint32_t> v(OAS_SOBOL_BLOCK_DIMS * 32);
        oas_sobol_directions(v.data());
        return v;
    }();
    return table;
}

Divisor makeDivisor(std::uint32_t d)
{
    if (d == 0) throw std::invalid_argument("makeDivisor: division by zero");
    Divisor out;
    oas_divisor(d, &out.recip, &out.shift);
    return out;
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
    return name == "oa" || samplerInfo(name).code < OAS_RANDOM;
}

std::string constructionName(std::uint32_t construction)
{
    for (auto& [name, info] : samplerTable())
        if (info.code == construction) return name;
    return "unknown(" + std::to_string(construction) + ")";
}

PrimePower primePower(std::uint32_t q)
{
    PrimePower out;
    if (!oas_prime_power(q, &out.p, &out.k)) return {};
    return out;
}

std::uint32_t primitivePolynomial(std::uint32_t p, std::uint32_t k)
{
    const std::uint32_t q = powCapped(p, k, kMaxFieldQ + 1);
    if (primePower(p).k != 1 || k < 1 || q == 0)
        throw InvalidArgument("GF(" + std::to_string(p) + "^" + std::to_string(k) + ") is not supported: need p prime and p^k <= 65536");
    return oas_primitive_polynomial(p, k);
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
    case OAS_BOSE:
    case OAS_BOSE_BUSH:
    case OAS_ADDELMAN_KEMPTHORNE:
        for (std::uint64_t q = 2; q <= 4096; ++q) consider(info.code == OAS_BOSE ? q * q : 2 * q * q);
        break;
    case OAS_BUSH:
    case OAS_CMJND:
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
    if (info.code == OAS_CMJND && request.strength == 0 && request.dims > 24)
        throw InvalidArgument("cmjnd: dims " + std::to_string(request.dims) +
                              " is too many for one full factorial (s^d <= 2^24 needs d <= 24); pass --strength d to pad with blocks of d dims");
    const bool strengthTwoOnly = info.code == OAS_BOSE || info.code == OAS_BOSE_BUSH ||
                                 info.code == OAS_ADDELMAN_KEMPTHORNE;
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
            if (code >= OAS_RANDOM) continue;
            std::vector<std::uint32_t> strengths;
            if (code == OAS_BUSH || code == OAS_CMJND)
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
        const bool lambdaOne = c.pat.construction == OAS_BOSE || c.pat.construction == OAS_BUSH;
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
    if (p.construction < OAS_RANDOM) {
        out << " q=" << p.s << " N=" << p.N << " t=" << p.strength << " " << offsetName(p.offset) << ", "
            << p.blockDims << " dims/block";
        if (p.fieldK > 1) out << ", GF(" << p.fieldP << "^" << p.fieldK << ")";
    } else {
        out << " N=" << p.N;
        if (p.construction == OAS_JITTERED_2D || p.construction == OAS_CMJ_2D)
            out << " grid " << p.aux << "x" << p.aux2;
    }
    return out.str();
}

}  // namespace oas
