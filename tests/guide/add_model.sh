#!/usr/bin/env bash
# docs/adding-a-model.md, followed to the letter in a copy of the tree: a throwaway family
# "guidetest" (Lambert plus an unnormalised Blinn-Phong lobe) is added by writing the files
# the guide's table lists, and nothing else; the build picks it up, the tests the guide
# names pass for it, and git sees exactly the table's files changed. A new place that must
# be edited to add a model (a list in a test, a table in a command) fails this check until
# the guide says so.
#
#   tests/guide/add_model.sh [WORKDIR]     (run by scripts/test.sh; WORKDIR is removed first)
set -euo pipefail
src=$(cd "$(dirname "$0")/../.." && pwd)
work=${1:-$src/build-guide}
guide=$src/docs/adding-a-model.md
fail() { echo "FAIL: adding a model by the guide: $*" >&2; exit 1; }
after_first() { # REGEX LINE FILE: LINE inserted after the first line matching REGEX
  awk -v re="$1" -v add="$2" '{ print } !done && $0 ~ re { print add; done = 1 }' "$3" > "$3.new" && mv "$3.new" "$3"
}
command -v git >/dev/null || fail "git is not installed (Debian package git)"

rm -rf "$work"
tree=$work/tree
mkdir -p "$tree"
# The tracked and new files as they are in the working tree (uncommitted edits included).
(cd "$src" && git ls-files -z --cached --others --exclude-standard | xargs -0 cp --parents -t "$tree" 2>/dev/null) || true
cd "$tree"
git init -q && git add -A && git -c user.name=guide -c user.email=guide@localhost commit -qm base

# The files the guide's table says to touch, with "mine" as the family's name.
mapfile -t listed < <(sed -n '/^| file | what |/,/^$/p' "$guide" | grep -oE '^\| `[^`]+`' |
                      sed -E 's/^\| `([^`]+)`/\1/; s/mine/guidetest/g' | sort)
[ "${#listed[@]}" -ge 3 ] || fail "no table of files in $guide"

name=guidetest
models_dir=$(dirname "$(printf '%s\n' "${listed[@]}" | grep -m1 "/$name\.c$")")
[ -d "$models_dir" ] || fail "the guide's family file is not in an existing folder"
for f in "${listed[@]}"; do
  case $f in
    */$name.c)
      cat > "$f" <<'EOF'
/* guidetest (tests/guide/add_model.sh): f = rho_d/pi + rho_s (n + 2) / (8 pi) NH^n, an
 * unnormalised Blinn-Phong lobe; not energy conserving for small n. */
#include "family.h"
#include "terms.h"

#include <math.h>

static void lobe_guidetest(const bf_model *m, int lobe, const double *s, const bf_geometry *g, size_t i0,
                           size_t cnt, double *S, double *dS)
{
    (void)m;
    (void)lobe;
    const double n = s[0], norm = (n + 2.0) / (8.0 * M_PI);
    for (size_t j = 0; j < cnt; j++) {
        size_t i = i0 + j;
        double v = 0.0, dn = 0.0;
        if (g->hz[i] > 0.0) {
            double lg = bf_log_nh(g->hz[i], g->sin2h[i]), t = n * lg;
            v = t > -665.0 ? norm * exp(t) : 0.0;
            dn = v * (1.0 / (n + 2.0) + lg);
        }
        S[j] = v;
        if (dS)
            dS[j] = dn;
    }
}

static bf_status configure(bf_model *m, bf_error *err)
{
    m->energy_conserving = 0; /* the lobe is not normalised */
    bf_status rc;
    if ((rc = bf_model_add_param(m, "rho_d", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, 0, BF_ROLE_DIFFUSE, err)) ||
        (rc = bf_model_add_param(m, "rho_s", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, 1, BF_ROLE_WEIGHT, err)) ||
        (rc = bf_model_add_param(m, "n", 0, 0.0, 1e4, 50.0, BF_SCALE_LOG1P, 1, BF_ROLE_EXPONENT, err)))
        return rc;
    return BF_OK;
}

const bf_family bf_family_guidetest = {
    .info = {.name = "guidetest", .summary = "guide check", .reference = "tests/guide/add_model.sh",
             .options = NULL, .lobes = 0, .anisotropic = 0},
    .configure = configure,
    .eval = bf_eval_diffuse_lobes,
    .lobe = lobe_guidetest,
};
EOF
      ;;
    */families.def)
      grep -q '^BF_FAMILY(' "$f" || fail "$f has no BF_FAMILY lines"
      echo "BF_FAMILY($name)" >> "$f" ;;
    */test_values_$name.c)
      cat > "$f" <<'EOF'
/* guidetest's values against its formula, written out from the angles. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>

#include "support.h"

static double ref(double rd, double rs, double n, double ti, double pi_, double to, double po)
{
    double L[3], V[3];
    ts_dirs_deg(ti, pi_, to, po, L, V);
    double H[3] = {L[0] + V[0], L[1] + V[1], L[2] + V[2]};
    double nh = H[2] / sqrt(H[0] * H[0] + H[1] * H[1] + H[2] * H[2]);
    return rd / M_PI + rs * (n + 2.0) / (8.0 * M_PI) * pow(nh, n);
}

static void test_values(void **state)
{
    (void)state;
    bf_model *m = NULL;
    assert_int_equal(bf_model_new("guidetest", 1, &m, NULL), BF_OK);
    const double x[3] = {0.3, 0.6, 20.0};
    /* Normal incidence and view: NH = 1. */
    ts_assert_rel(ts_eval1(m, x, 0.0, 0.0, 0.0, 0.0, 0), 0.3 / M_PI + 0.6 * 22.0 / (8.0 * M_PI), 1e-13, "normal");
    for (int t = 0; t < 50; t++) {
        double ti = 1.7 * t, to = 88.0 - 1.5 * t, po = 7.3 * t;
        ts_assert_rel(ts_eval1(m, x, ti, 0.0, to, po, 0), ref(0.3, 0.6, 20.0, ti, 0.0, to, po), 1e-12, "formula");
    }
    bf_model_free(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_values)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
EOF
      ;;
    */test_fit_recovery.c) # blinn_phong's case, for the same parameters
      grep -q '^ *{"blinn_phong",' "$f" || fail "$f has no blinn_phong case to follow"
      after_first '^ *[{]"blinn_phong",' "$(grep -m1 '^ *{"blinn_phong",' "$f" | sed "s/blinn_phong/$name/")" "$f" ;;
    */models.md)
      grep -q '^| \[`blinn_phong`\]' "$f" || fail "$f has no row for blinn_phong"
      after_first '^[|] [[]`blinn_phong`[]]' "| [\`$name\`](#$name) | guide check | | |" "$f"
      printf '\n### %s\n\n`f = rho_d / pi + rho_s (n + 2) / (8 pi) NH^n`: `rho_d`, `rho_s` colour, `n` scalar.\n' \
        "$name" >> "$f" ;;
    *) fail "the guide lists $f, which this check does not know how to write: teach it" ;;
  esac
done

# Nothing but the listed files changed.
changed=$(git status --porcelain --untracked-files=all | sed -E 's/^.. //' | sort)
[ "$changed" = "$(printf '%s\n' "${listed[@]}")" ] ||
  fail "changed files differ from the guide's table: $(echo $changed)"

# The build finds the new files; the tests the guide names pass.
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
tests=(test_gradients test_reciprocity test_energy test_extremes test_model_api test_param_roles test_fit_recovery
       test_values_$name)
cmake --build build -j "$(nproc)" --target brdfit_cmd brdfit_synth "${tests[@]}" >/dev/null ||
  fail "the tree with $name does not build"
build/cmd/brdfit models | grep -q "^$name\b" || fail "brdfit models does not list $name"
ctest --test-dir build --output-on-failure -j "$(nproc)" -R "^($(IFS='|'; echo "${tests[*]}")|cli_docs_models)\$" ||
  fail "the guide's tests do not pass with $name"
echo "adding a model by the guide: ${#listed[@]} files, as listed; ${#tests[@]} tests and cli_docs_models pass"
rm -rf "$work"
