/* Matrix of restitution and the eMD* collision rule from the embedded default table.
 *
 * Build (after `cargo build --release -p emdstar-table-capi`):
 *   gcc examples/c/lookup.c -I crates/table-capi/include \
 *       target/release/libemdstar_table_c.a -lpthread -ldl -lm -o lookup
 */
#include <math.h>
#include <stdio.h>
#include "emdstar_table.h"

int main(void) {
    EmdstarTable *table = emdstar_table_open_default(EMDSTAR_MODEL_LINEAR);
    if (!table) {
        fprintf(stderr, "open failed: %s\n", emdstar_table_last_error());
        return 1;
    }
    EmdstarTableInfo info;
    emdstar_table_info(table, &info);
    printf("model %d, tolerance %.1e, %zu box parameters\n", (int)info.model, info.tolerance,
           info.box_len);
    for (size_t i = 0; i < info.box_len; i++) {
        const char *name;
        double lo, hi;
        emdstar_table_box_parameter(table, i, &name, &lo, &hi);
        printf("  %s in [%g, %g]\n", name, lo, hi);
    }
    /* Two glass-like spheres, R = 5 mm, rho = 2500 kg/m^3, k = 1e5 N/m, gamma = 0.1 kg/s:
     * the pair handle checks and folds the law and the pair once. */
    const double pi = 3.14159265358979323846;
    double r = 0.005, m = 4.0 / 3.0 * pi * r * r * r * 2500.0;
    EmdstarPair *pair = emdstar_pair_linear(table, 1e5, 0.1, r, m, r, m);
    if (!pair) {
        fprintf(stderr, "pair failed: %s\n", emdstar_table_last_error());
        emdstar_table_close(table);
        return 1;
    }
    int failed = 1;
    EmdstarMor mor;
    EmdstarStatus st = emdstar_pair_lookup(pair, 1.0, 0.5, 0, &mor);
    if (st != EMDSTAR_STATUS_OK) {
        fprintf(stderr, "lookup failed (%d): %s\n", (int)st, emdstar_table_last_error());
        goto done;
    }
    printf("eps_r = %.12g\n", mor.eps_r);
    printf("eps_n = %.12g\n", -mor.eps_rdot);
    printf("eps_phi = %.12g rad\n", mor.eps_phi);
    printf("duration = %.6g s\n", mor.eps_t * mor.time_scale);
    /* The same impact, solved exactly from its scaled parameters (Eqs. 41-43):
     * l~ = l omega / v_n, c_phi = l~ v_t / v_n, c_dis = gamma / (m_eff omega). */
    double m_eff = m / 2, omega = sqrt(1e5 / m_eff), lt = 2 * r * omega / 1.0;
    EmdstarMor exact;
    emdstar_mor_exact_scaled(EMDSTAR_MODEL_LINEAR, lt, lt * 0.5, 0.1 / (m_eff * omega), &exact);
    printf("exact eps_n = %.12g\n", -exact.eps_rdot);
    /* A very slow impact lies outside the box (b too large): refused, never
     * extrapolated, unless the caller asks for the exact fallback (counted). */
    st = emdstar_pair_lookup(pair, 1e-5, 0.0, 0, &mor);
    printf("out of box: status %d (%s)\n", (int)st, emdstar_table_last_error());
    st = emdstar_pair_lookup(pair, 1e-5, 0.0, 1, &mor);
    printf("with fallback: status %d, source %d, fallbacks %llu\n", (int)st, (int)mor.source,
           (unsigned long long)emdstar_pair_fallbacks(pair));
    /* The lab-frame collision of two spheres touching along x, approaching. */
    EmdstarBody b1 = {{0, 0, 0}, {-0.5, 0.25, 0}}, b2 = {{-2 * r, 0, 0}, {0.5, -0.25, 0}};
    EmdstarCollision c;
    st = emdstar_pair_collide(pair, m, m, &b1, &b2, 1, &c);
    if (st != EMDSTAR_STATUS_OK) {
        fprintf(stderr, "collide failed (%d): %s\n", (int)st, emdstar_table_last_error());
        goto done;
    }
    printf("after: v1 = (%.6g, %.6g, %.6g), tau = %.6g s\n", c.after[0].velocity[0],
           c.after[0].velocity[1], c.after[0].velocity[2], c.duration);
    printf("momentum x after = %.3e\n", m * (c.after[0].velocity[0] + c.after[1].velocity[0]));
    failed = 0;
done:
    emdstar_pair_free(pair);
    emdstar_table_close(table);
    if (failed) return 1;
    /* A file that is not a table: NULL and a message. */
    EmdstarTable *bad = emdstar_table_open("/nonexistent/table.npz");
    printf("bad file: %s (%s)\n", bad ? "opened?!" : "NULL", emdstar_table_last_error());
    return 0;
}
