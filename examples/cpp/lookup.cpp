// The MoR and the collision rule of Hertz spheres through the C++ RAII header.
//
// Build (after `cargo build --release -p emdstar-table-capi`):
//   g++ -std=c++17 examples/cpp/lookup.cpp -I examples/cpp -I crates/table-capi/include \
//       target/release/libemdstar_table_c.a -lpthread -ldl -lm -o lookup_cpp
#include <cmath>
#include <cstdio>

#include "emdstar_table.hpp"

int main() {
    try {
        auto table = emdstar::Table::open_default(EMDSTAR_MODEL_HERTZ);
        auto info = table.info();
        std::printf("hertz table: tolerance %.1e, first box parameter %s\n", info.tolerance,
                    table.box_parameter(0).name.c_str());
        // Steel-like spheres, R = 1 cm, rho = 7800 kg/m^3, Y = 200 GPa, nu = 0.3, A = 1 us.
        const double pi = 3.14159265358979323846, r = 0.01;
        const double m = 4.0 / 3.0 * pi * r * r * r * 7800.0;
        auto pair = emdstar::Pair::hertz(table, 2e10, 0.3, 1e-6, r, m, r, m);
        EmdstarMor mor = pair.lookup(1.0, 0.3);
        std::printf("eps_n = %.12g\n", -mor.eps_rdot);
        std::printf("duration = %.6g s\n", mor.eps_t * mor.time_scale);
        try {
            pair.lookup(1e-9, 0.0);  // far too slow for the box
            std::printf("out of box not refused\n");
            return 1;
        } catch (const emdstar::Error &e) {
            std::printf("out of box: status %d\n", static_cast<int>(e.status()));
        }
        EmdstarMor exact = pair.lookup(1e-9, 0.0, emdstar::Fallback::Exact);
        std::printf("with fallback: source %d, fallbacks %llu\n", static_cast<int>(exact.source),
                    static_cast<unsigned long long>(pair.fallbacks()));
        // A sphere dropping onto the floor z = 0 at 1 m/s.
        auto wall = emdstar::Pair::hertz(table, 2e10, 0.3, 1e-6, r, m, 0.0, 0.0);
        const double up[3] = {0, 0, 1};
        EmdstarBody ball = {{0, 0, r}, {0.2, 0, -1.0}};
        EmdstarCollision c = wall.collide_wall(ball, up, emdstar::Fallback::Exact);
        std::printf("bounce: v_z = %.6g m/s, v_x = %.6g m/s\n", c.after[0].velocity[2],
                    c.after[0].velocity[0]);
    } catch (const emdstar::Error &e) {
        std::fprintf(stderr, "error %d: %s\n", static_cast<int>(e.status()), e.what());
        return 1;
    }
    return 0;
}
