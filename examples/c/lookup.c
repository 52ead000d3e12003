/* Matrix of restitution of one impact from the embedded default table.
 *
 * Build (after `cargo build --release -p emdstar-table-capi`):
 *   gcc examples/c/lookup.c -I crates/table-capi/include \
 *       target/release/libemdstar_table_c.a -lpthread -ldl -lm -o lookup
 */
#include <stdio.h>
#include "emdstar_table.h"

int main(void) {
    EmdstarTable *table = emdstar_table_open_default(EMDSTAR_MODEL_LINEAR);
    if (!table) {
        fprintf(stderr, "open failed: %s\n", emdstar_table_last_error());
        return 1;
    }
    /* Two glass-like spheres, R = 5 mm, rho = 2500 kg/m^3, k = 1e5 N/m, gamma = 0.1 kg/s,
     * meeting at v_n = 1 m/s, v_t = 0.5 m/s. */
    const double pi = 3.14159265358979323846;
    double r = 0.005, m = 4.0 / 3.0 * pi * r * r * r * 2500.0;
    EmdstarMor mor;
    EmdstarStatus st = emdstar_table_lookup_linear(table, 1e5, 0.1, r, m, r, m, 1.0, 0.5, &mor);
    if (st != EMDSTAR_STATUS_OK) {
        fprintf(stderr, "lookup failed (%d): %s\n", (int)st, emdstar_table_last_error());
        emdstar_table_close(table);
        return 1;
    }
    printf("eps_r = %.12g\n", mor.eps_r);
    printf("eps_n = %.12g\n", -mor.eps_rdot);
    printf("eps_phi = %.12g rad\n", mor.eps_phi);
    printf("duration = %.6g s\n", mor.eps_t * mor.time_scale);
    /* A very stiff, very slow impact lies outside the paper's box (b too large): it is
     * refused, never extrapolated; a caller would solve it exactly instead. */
    st = emdstar_table_lookup_linear(table, 1e12, 0.1, r, m, r, m, 1e-3, 5e-4, &mor);
    printf("out of box: status %d (%s)\n", (int)st, emdstar_table_last_error());
    emdstar_table_close(table);
    return 0;
}
