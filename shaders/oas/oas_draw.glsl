// oas_draw.glsl - several consecutive dimensions of one sample in one call.
// Part of the oas GLSL library; include "oas.glsl" rather than this file.
#ifndef OAS_DRAW_GLSL
#define OAS_DRAW_GLSL

/// Most dimensions one oas_draw returns: a path tracer's camera (pixel, lens, time) or one path
/// vertex (light, BSDF, lobe, roulette) fits.
const uint OAS_DRAW_MAX = 8u;

/// Dimensions [firstDim, firstDim + dimCount) of one sample: u[k] is dimension firstDim + k for
/// k < dimCount and 0 beyond.
struct OasDraw {
    float u[OAS_DRAW_MAX];
};

/// Dimensions [firstDim, firstDim + dimCount) of sample `index` (dimCount <= OAS_DRAW_MAX; u[k] = 0
/// for k >= dimCount), each equal bit for bit to oas_sample(p, pixelSeed, index, firstDim + k).
/// Why: a renderer draws its dimensions in groups (a camera ray, a path vertex), and the row state
/// of an OA block (the sample's row of the block's shuffled array, oas_row) is the same for every
/// dimension of that block. This makes it once per OA block the group touches and reuses it for
/// that block's columns, where oas_sample per dimension makes it again every time; baselines go
/// through oas_baseline_sample. Calling it at one site (a loop over the groups) also keeps the
/// shader small: the compiler inlines the sampler at every call site.
/// Fixed work: the loop runs OAS_DRAW_MAX times and unrolls (dimensions past dimCount are skipped).
/// Speed: the loop makes a row wherever a block may start, and lavapipe (like any SIMD machine
/// that predicates branches) pays for each: up to OAS_DRAW_MAX rows a draw. An includer whose
/// draws never span more than R blocks (R = 2 for draws of up to 8 dimensions where blocks hold
/// 7 or more: Bose and Bush with q >= 7, Addelman-Kempthorne, Bose-Bush with q >= 4) may define
/// OAS_STATIC_DRAW_BLOCKS R (a constant or specialization constant, 1..OAS_DRAW_MAX) before the
/// include: then it makes R rows, and a draw that spans more gives NaN in every value, never
/// wrong numbers. Measured in examples/smallpt (docs/EMBEDDING.md): R = 2 took its frame from
/// 3.62x to 2.49x its own hash's on lavapipe.
/// For many samples of one pass, the OasBlock/OasColumn fast path shares more (oas.glsl's API).
OasDraw oas_draw(OasPattern pat, uint pixelSeed, uint index, uint firstDim, uint dimCount)
{
    OasDraw draw;
    bool baseline = OAS_CONSTRUCTION(pat) >= OAS_RANDOM;
    // The OA block and column of dimension firstDim + k, advanced one column per k (no division
    // per dimension); baselines have no blocks (and their blockDims is not a divisor).
    uint block = baseline ? 0u : firstDim / pat.blockDims;
    uint col = baseline ? 0u : firstDim - block * pat.blockDims;
#ifdef OAS_STATIC_DRAW_BLOCKS
    // The includer's promise: a draw spans at most OAS_STATIC_DRAW_BLOCKS blocks. One row per block
    // in reach, made unconditionally (g[j]: block + j); e: whether this draw keeps the promise
    // (its last dimension's block is in reach), else every value is NaN. Local names from the
    // header's list only (an includer's macro of another name must not break this path).
    OasRow g[OAS_STATIC_DRAW_BLOCKS];
    OAS_UNROLL for (uint j = 0u; j < OAS_STATIC_DRAW_BLOCKS; ++j)
        if (!baseline) g[j] = oas_row(pat, pixelSeed, index, block + j);
    bool e = baseline || dimCount == 0u || (col + dimCount - 1u) / pat.blockDims < OAS_STATIC_DRAW_BLOCKS;
    OAS_UNROLL for (uint k = 0u; k < OAS_DRAW_MAX; ++k) {
        draw.u[k] = 0.0f;
        if (k < dimCount) {
            if (baseline) {
                draw.u[k] = oas_baseline_sample(pat, pixelSeed, index, firstDim + k);
            } else {
                // Dimension firstDim + k's block (as its row r) and column c, by subtraction.
                uint c = col + k;
                OasRow r = g[0];
                OAS_UNROLL for (uint j = 1u; j < OAS_STATIC_DRAW_BLOCKS; ++j)
                    if (c >= pat.blockDims) {
                        c -= pat.blockDims;
                        r = g[j];
                    }
                draw.u[k] = e ? oas_row_dim(pat, r, min(c, pat.blockDims - 1u)) : uintBitsToFloat(0x7fc00000u);
            }
        }
    }
#else
    OasRow r;
    OAS_UNROLL for (uint k = 0u; k < OAS_DRAW_MAX; ++k) {
        draw.u[k] = 0.0f;
        if (k < dimCount) {
            if (baseline) {
                draw.u[k] = oas_baseline_sample(pat, pixelSeed, index, firstDim + k);
            } else {
                if (k == 0u || col == pat.blockDims) {
                    if (k != 0u) {
                        block += 1u;
                        col = 0u;
                    }
                    r = oas_row(pat, pixelSeed, index, block);
                }
                draw.u[k] = oas_row_dim(pat, r, col);
                col += 1u;
            }
        }
    }
#endif
    return draw;
}

#endif // OAS_DRAW_GLSL
