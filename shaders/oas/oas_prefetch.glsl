// oas_prefetch.glsl - the prefetch recipe: a run of consecutive samples of one dimension, written
// to the includer's buffer, with what the run's samples share made once per pass.
// Part of the oas GLSL library: oas.glsl includes it when the includer has defined
// OAS_PREFETCH_STORE(at, v) (how to store value v at element `at` of its buffer), before
// including oas.glsl. Shared with C++ through host/oas/glsl_compat.hpp, like the rest.
#ifndef OAS_PREFETCH_GLSL
#define OAS_PREFETCH_GLSL

/// Writes dimension `dim` of samples [index, index + n) of the pixel with seed `seed`: sample
/// index + k's value, equal bit for bit to oas_sample(pat, seed, index + k, dim), through
/// OAS_PREFETCH_STORE(offset + k * stride, value).
///
/// Why: a renderer that draws its samples where it uses them (oas_sample, oas_draw) makes an OA
/// block's and column's state (seeds, permutation keys, field constants) again for every value;
/// per value that is several times the value's own work. A small kernel dispatched before the
/// tracer, one invocation per (pixel, dimension), calls this for the samples the tracer's next
/// dispatch takes; the state is then made once per pass and each value costs its row and its
/// stratum point (docs/EMBEDDING.md, "The prefetch recipe", has the kernel and the measured
/// frame cost; examples/smallpt uses it). Baselines take oas_baseline_sample per value.
/// Loops: n iterations and one per pass the run touches, all uniform when every invocation of a
/// dispatch has the same index and n; on lavapipe keep n below its cap of 65535 per invocation.
void oas_prefetch(OasPattern pat, uint seed, uint dim, uint index, uint n, uint offset, uint stride)
{
    if (OAS_CONSTRUCTION(pat) >= OAS_RANDOM) {
        for (uint k = 0u; k < n; ++k) OAS_PREFETCH_STORE(offset + k * stride, oas_baseline_sample(pat, seed, index + k, dim));
        return;
    }
    uint block = dim / pat.blockDims;
    uint col = dim - block * pat.blockDims;
    uint k = 0u;
    while (k < n) {  // one pass of the run per iteration
        OasBlock b = oas_block(pat, seed, index + k, block);
        OasColumn c = oas_column(pat, b.seed, col);
        uint end = min(n, b.firstIndex + pat.N - index);  // the pass's last sample + 1, as k
        for (; k < end; ++k) OAS_PREFETCH_STORE(offset + k * stride, oas_column_dim(pat, c, oas_block_row(b, index + k)));
    }
}

#endif // OAS_PREFETCH_GLSL
