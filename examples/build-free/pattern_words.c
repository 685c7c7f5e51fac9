/* pattern_words.c - the host side of oas with no build system: compile it together with
 * oas_pattern.c (docs/EMBEDDING.md, "Without a build system"):
 *   cc -std=c99 -I<oas>/host <oas>/host/oas/oas_pattern.c pattern_words.c -o pattern_words
 * It builds the pattern a shader receives and the specialization its pipeline is made with,
 * and prints both as a host would upload them. tests/consumers/build_free.sh runs it. */
#include <stdio.h>

#include "oas/oas_pattern.h"

int main(void)
{
    OasPattern pattern;
    OasSpecialization spec;
    char why[256];
    const uint32_t* words = (const uint32_t*)&pattern;
    size_t w;
    /* A count Bose cannot make: the refusal names the value and the nearest counts it can. */
    if (oas_make_pattern(OAS_BOSE, 63, 0, OAS_OFFSET_CMJ, &pattern, why, sizeof why) == 0) return 1;
    printf("refused: %s\n", why);
    if (oas_make_pattern(OAS_BOSE, 64, 0, OAS_OFFSET_CMJ, &pattern, why, sizeof why) != 0) {
        fprintf(stderr, "%s\n", why);
        return 1;
    }
    printf("pattern:");
    for (w = 0; w < sizeof pattern / sizeof *words; ++w) printf(" %s=%u", oas_pattern_field_name(w), (unsigned)words[w]);
    oas_specialization(&pattern, &spec);
    printf("\nspecialization: construction=%u offset=%u fieldKind=%u fieldDegree=%u smallN=%u indexBits=%u\n",
           (unsigned)spec.construction, (unsigned)spec.offset, (unsigned)spec.fieldKind, (unsigned)spec.fieldDegree,
           (unsigned)spec.smallN, (unsigned)spec.indexBits);
    return 0;
}
