// The C++ API over the C pattern builder (oas_pattern.c, which makes every value choice): names,
// validation messages with the nearest valid counts, and the OA chooser.
#include "oas/pattern.hpp"

#include <algorithm>
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

/// The construction code of a sampler name; the names are the C builder's table
/// (oas_construction_name), the only one.
std::uint32_t samplerCode(const std::string& name)
{
    std::uint32_t code = 0;
    if (oas_construction_from_name(name.c_str(), &code) != 0) {
        std::string list = "oa";
        for (auto& n : samplerNames()) list += ", " + n;
        throw InvalidArgument("sampler '" + name + "' is unknown: valid samplers are " + list);
    }
    return code;
}

/// The first `count` sample counts of a construction at strength 2, "a, b, c ...", from the C
/// builder's rules (oas_valid_counts), for the descriptions.
std::string firstCounts(std::uint32_t code, std::size_t count)
{
    std::vector<std::uint32_t> counts(count);
    counts.resize(std::min(count, oas_valid_counts(code, 2, 1, OAS_MAX_SAMPLES, counts.data(), count)));
    std::string out;
    for (auto c : counts) out += std::to_string(c) + ", ";
    return out.substr(0, out.size() - 2) + " ...";
}

/// Faure's default dimensions per block: all of them up to 16 (base q >= d, so more dimensions in
/// one block mean a coarser base: 16 keeps q^2 = 256 strata in 2D within a few hundred samples;
/// blocks past the first are scrambled independently, as the OAs pad).
constexpr std::uint32_t kFaureDefaultBlockDims = 16;

std::uint32_t defaultStrength(std::uint32_t code, std::uint32_t dims)
{
    if (code == OAS_CMJND) return std::max<std::uint32_t>(dims, 1);
    if (code == OAS_FAURE) return std::clamp<std::uint32_t>(dims, 2, kFaureDefaultBlockDims);
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
    return Pattern(built);
}

std::string countList(const std::vector<std::uint32_t>& counts)
{
    std::string out;
    for (auto c : counts) out += (out.empty() ? "" : ", ") + std::to_string(c);
    return out.empty() ? "none" : out;
}

/// Nearest valid counts below and above spp (either may be missing).
std::vector<std::uint32_t> nearestCounts(const std::string& sampler, std::uint32_t t, std::uint32_t dims, std::uint32_t spp)
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
        throw InvalidArgument("spp " + std::to_string(r.spp) + " is out of range: valid 1 .. " + std::to_string(kMaxSamples));
    if (r.dims < 1 || r.dims > kMaxDims)
        throw InvalidArgument("dims " + std::to_string(r.dims) + " is out of range: valid 1 .. " + std::to_string(kMaxDims));
    if (r.strength > OAS_MAX_STRENGTH)
        throw InvalidArgument("strength " + std::to_string(r.strength) + " is out of range: valid 2 .. " +
                              std::to_string(OAS_MAX_STRENGTH));
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
    static const std::vector<std::string> names = [] {
        std::vector<std::string> out;
        for (std::size_t i = 0; oas_construction_at(i) != 0; ++i) out.push_back(oas_construction_name(oas_construction_at(i)));
        return out;
    }();
    return names;
}

std::string samplerDescription(const std::string& name)
{
    if (name == "oa") return "the best orthogonal array for (spp, dims, strength), chosen and explained";
    const std::uint32_t code = samplerCode(name);
    switch (code) {
    case OAS_BOSE:
        return "Bose OA(q^2, q+1, q, 2), q prime power <= " + std::to_string(OAS_MAX_BOSE_Q) + ": N = " + firstCounts(code, 8);
    case OAS_BUSH:
        return "Bush OA(q^t, q+1, q, t), q prime power >= t: strength t";
    case OAS_BOSE_BUSH:
        return "Bose-Bush OA(2q^2, 2q+1, q, 2), q = 2^k: N = " + firstCounts(code, 5);
    case OAS_ADDELMAN_KEMPTHORNE:
        return "Addelman-Kempthorne OA(2q^2, 2q+1, q, 2), q odd prime power: N = " + firstCounts(code, 4);
    case OAS_CMJND:
        return "CMJND OA(s^d, d, s, d): full factorial, any s >= 2, strength d";
    case OAS_RANDOM:
        return "independent uniform random (baseline)";
    case OAS_JITTERED_2D:
        return "jittered nx*ny grid per dimension pair, padded (baseline)";
    case OAS_CMJ_2D:
        return "correlated multi-jittered 2D per pair, padded (Kensler 2013; baseline)";
    case OAS_ZERO_TWO:
        return "Owen-scrambled (0,2)-sequence per pair, padded (baseline)";
    case OAS_HALTON:
        return "Halton with random digit permutations, blocks of " + std::to_string(OAS_HALTON_BLOCK_DIMS) + " dims (baseline)";
    case OAS_SOBOL:
        return "Owen-scrambled Sobol, hash-based scramble (after Burley 2020), blocks of " + std::to_string(OAS_SOBOL_BLOCK_DIMS) +
               " dims (baseline; Joe-Kuo direction numbers)";
    case OAS_SOBOL_OWEN:
        return "Owen-scrambled Sobol, per-bit nested uniform scramble, blocks of " + std::to_string(OAS_SOBOL_BLOCK_DIMS) +
               " dims (baseline; Joe-Kuo direction numbers)";
    case OAS_SOBOL_BURLEY:
        return "Sobol-Burley: 4D Owen-scrambled Sobol padded with hash-shuffled indices (Burley 2020; Cycles' default; "
               "baseline)";
    case OAS_FAURE:
        return "progressive: Owen-scrambled generalized Faure (0,s)-sequence in base q >= d (d = strength: dims per block, "
               "default min(dims, " + std::to_string(kFaureDefaultBlockDims) + ")); N = the smallest q^K >= spp, every prefix of "
               "q^m samples a (0,m,d)-net";
    }
    return name;  // a construction the C builder names but this list does not describe yet
}

bool isOrthogonalArray(const std::string& name)
{
    return name == "oa" || samplerCode(name) < OAS_RANDOM;
}

std::string constructionName(std::uint32_t construction)
{
    if (const char* name = oas_construction_name(construction)) return name;
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
        throw InvalidArgument("GF(" + std::to_string(p) + "^" + std::to_string(k) +
                              ") is not supported: need p prime and p^k <= 65536");
    return oas_primitive_polynomial(p, k);
}

std::vector<std::uint32_t> validCounts(const std::string& sampler, std::uint32_t strength, std::uint32_t dims, std::uint32_t lo,
                                       std::uint32_t hi)
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
    const std::uint32_t code = samplerCode(sampler);
    const std::uint32_t t = strength ? strength : defaultStrength(code, dims);
    // The baselines take every count: list the first 64 of the range, enough for any message.
    const std::size_t total = oas_valid_counts(code, t, lo, hi, nullptr, 0);
    out.resize(code >= OAS_RANDOM ? std::min<std::size_t>(total, 64) : total);
    oas_valid_counts(code, t, lo, hi, out.data(), out.size());
    return out;
}

Pattern makePattern(const PatternRequest& request)
{
    checkCommon(request);
    if (request.sampler == "oa") return chooseOrthogonalArray(request).pattern;
    const std::uint32_t code = samplerCode(request.sampler);
    const std::uint32_t offset = offsetCode(request.offset);
    const std::uint32_t t = request.strength ? request.strength : defaultStrength(code, request.dims);
    if (code == OAS_CMJND && request.strength == 0 && request.dims > 24)
        throw InvalidArgument(
            "cmjnd: dims " + std::to_string(request.dims) +
            " is too many for one full factorial (s^d <= 2^24 needs d <= 24); pass --strength d to pad with blocks of d dims");
    const bool strengthTwoOnly = code == OAS_BOSE || code == OAS_BOSE_BUSH || code == OAS_ADDELMAN_KEMPTHORNE;
    if (strengthTwoOnly && t != 2)
        throw InvalidArgument("sampler '" + request.sampler + "' has strength 2 only (strength " + std::to_string(t) +
                              " asked): use bush or cmjnd for strength 3 and more");
    std::string why;
    Pattern pat = exactPattern(code, request.spp, t, offset, why);
    if (pat.N != 0) return pat;
    const auto near = nearestCounts(request.sampler, t, request.dims, request.spp);
    if (request.roundUp && !near.empty() && near.back() > request.spp) return exactPattern(code, near.back(), t, offset, why);
    // The C builder's message names the nearest valid counts already (the same oas_valid_counts).
    throw InvalidArgument("sampler '" + request.sampler + "' (strength " + std::to_string(t) + ") cannot make exactly spp " +
                          std::to_string(request.spp) + ": " + why +
                          (near.empty() ? "; nearest valid spp: none" : " (or allow rounding up)"));
}

namespace {
/// For a count no orthogonal array makes: the progressive sampler's offer, "; or the progressive
/// sampler faure takes any count: <what its prefix guarantees>", or "" where it cannot make spp.
std::string progressiveAlternative(const PatternRequest& request)
{
    std::string why;
    const Pattern p = exactPattern(OAS_FAURE, request.spp, defaultStrength(OAS_FAURE, request.dims), 0, why);
    if (p.N == 0) return "";
    return "; or the progressive sampler faure (--sampler faure) takes any count: " + prefixGuarantee(p, request.spp);
}
}  // namespace

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
            const std::uint32_t code = samplerCode(name);
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
                                  (near.empty() ? "" : " (or allow rounding up)") + progressiveAlternative(request));
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
    why << note << "chose " << describe(best.pat) << " for spp " << spp << ", " << request.dims << " dims, strength >= " << t
        << ": ";
    const std::uint32_t blocks = (request.dims + best.pat.blockDims - 1) / best.pat.blockDims;
    why << (blocks == 1 ? "one OA block covers every dimension" : std::to_string(blocks) + " independently randomized OA blocks")
        << ", every " << best.pat.strength << "-D projection within a block stratified into " << best.pat.s << "^"
        << best.pat.strength << " cells";
    if (candidates.size() > 1) {
        why << "; other candidates:";
        for (std::size_t i = 1; i < candidates.size(); ++i) why << " [" << describe(candidates[i].pat) << "]";
    }
    return {best.pat, best.name, why.str()};
}

std::string prefixGuarantee(const Pattern& p, std::uint32_t spp)
{
    if (p.construction != OAS_FAURE || spp == 0) return "";
    const std::uint32_t q = p.s, used = std::min(spp, p.N);
    std::uint32_t m = 0, qm = 1;
    while (std::uint64_t(qm) * q <= used) qm *= q, ++m;
    const std::uint32_t lambda = used / qm, whole = lambda * qm;
    std::ostringstream out;
    out << "the first " << used << " of the sequence's " << p.N << " samples: ";
    if (m == 0) {
        out << "fewer than q = " << q << ", so no dimension is stratified yet";
        return out.str();
    }
    const std::string net = "(0," + std::to_string(m) + "," + std::to_string(p.blockDims) + ")-net";
    out << "the first " << whole << " (" << lambda << " x " << q << "^" << m << ") are "
        << (lambda == 1 ? "a " + net : std::to_string(lambda) + " " + net + "s") << ": in every block of " << p.blockDims
        << " dims, every grid of q^k1 x ... x q^kd cells with k1 + ... + kd = " << m << " has " << lambda << " sample"
        << (lambda == 1 ? "" : "s") << " in each cell";
    if (whole < used) out << "; the " << used - whole << " after them start the next one";
    return out.str();
}

std::string describe(const Pattern& p)
{
    std::ostringstream out;
    out << constructionName(p.construction);
    if (p.construction < OAS_RANDOM) {
        out << " q=" << p.s << " N=" << p.N << " t=" << p.strength << " " << offsetName(p.offset) << ", " << p.blockDims
            << " dims/block";
        if (p.fieldK > 1) out << ", GF(" << p.fieldP << "^" << p.fieldK << ")";
    } else if (p.construction == OAS_FAURE) {
        out << " q=" << p.s << " N=" << p.N << " (" << p.aux << " digits), " << p.blockDims << " dims/block";
        if (p.fieldK > 1) out << ", GF(" << p.fieldP << "^" << p.fieldK << ")";
    } else {
        out << " N=" << p.N;
        if (p.construction == OAS_JITTERED_2D || p.construction == OAS_CMJ_2D) out << " grid " << p.aux << "x" << p.aux2;
    }
    return out.str();
}

}  // namespace oas
