// RAII wrapper over the C ABI of the emdstar matrix-of-restitution table reader
// (crates/table-capi/include/emdstar_table.h). Header only; C++17.
//
//   auto table = emdstar::Table::open_default(EMDSTAR_MODEL_HERTZ);
//   auto pair = emdstar::Pair::hertz(table, 1e9, 0.3, 1e-5, r, m, r, m);
//   EmdstarMor mor = pair.lookup(1.0, 0.5, emdstar::Fallback::Exact);
//
// Failures throw emdstar::Error (a std::runtime_error with the library's message and
// its status). Tables and pairs are movable, not copyable; a pair keeps its table's
// data alive, so the Table object may go first.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>

#include "emdstar_table.h"

namespace emdstar {

class Error : public std::runtime_error {
public:
    Error(EmdstarStatus status, const std::string &what)
        : std::runtime_error(what), status_(status) {}
    EmdstarStatus status() const noexcept { return status_; }

private:
    EmdstarStatus status_;
};

inline void check(EmdstarStatus status) {
    if (status != EMDSTAR_STATUS_OK) throw Error(status, emdstar_table_last_error());
}

enum class Fallback { None = 0, Exact = 1 };

class Table {
public:
    static Table open(const std::string &path) { return Table(emdstar_table_open(path.c_str())); }
    static Table open_default(EmdstarModel model) {
        return Table(emdstar_table_open_default(model));
    }
    Table(Table &&o) noexcept : t_(std::exchange(o.t_, nullptr)) {}
    Table &operator=(Table &&o) noexcept {
        std::swap(t_, o.t_);
        return *this;
    }
    Table(const Table &) = delete;
    Table &operator=(const Table &) = delete;
    ~Table() { emdstar_table_close(t_); }

    EmdstarTableInfo info() const {
        EmdstarTableInfo i;
        check(emdstar_table_info(t_, &i));
        return i;
    }
    struct Parameter {
        std::string name;
        double min, max;
    };
    Parameter box_parameter(std::size_t index) const {
        const char *name = nullptr;
        double lo = 0, hi = 0;
        check(emdstar_table_box_parameter(t_, index, &name, &lo, &hi));
        return {name, lo, hi};
    }
    EmdstarMor lookup_scaled(double l_tilde, double c_phi, double c_dis) const {
        EmdstarMor m;
        check(emdstar_table_lookup_scaled(t_, l_tilde, c_phi, c_dis, &m));
        return m;
    }
    const EmdstarTable *get() const noexcept { return t_; }

private:
    explicit Table(EmdstarTable *t) : t_(t) {
        if (!t_) throw Error(EMDSTAR_STATUS_BAD_FILE, emdstar_table_last_error());
    }
    EmdstarTable *t_;
};

class Pair {
public:
    /// Linear dashpot (k in N/m, gamma in kg/s); radius2 = mass2 = 0 for a wall.
    static Pair linear(const Table &t, double k, double gamma, double r1, double m1, double r2,
                       double m2) {
        return Pair(emdstar_pair_linear(t.get(), k, gamma, r1, m1, r2, m2));
    }
    /// Viscoelastic Hertz (Y in Pa, Poisson ratio, A in s); radius2 = mass2 = 0 for a wall.
    static Pair hertz(const Table &t, double young, double poisson, double a, double r1,
                      double m1, double r2, double m2) {
        return Pair(emdstar_pair_hertz(t.get(), young, poisson, a, r1, m1, r2, m2));
    }
    Pair(Pair &&o) noexcept : p_(std::exchange(o.p_, nullptr)) {}
    Pair &operator=(Pair &&o) noexcept {
        std::swap(p_, o.p_);
        return *this;
    }
    Pair(const Pair &) = delete;
    Pair &operator=(const Pair &) = delete;
    ~Pair() { emdstar_pair_free(p_); }

    EmdstarMor lookup(double normal_speed, double tangential_speed,
                      Fallback f = Fallback::None) const {
        EmdstarMor m;
        check(emdstar_pair_lookup(p_, normal_speed, tangential_speed, static_cast<int>(f), &m));
        return m;
    }
    EmdstarCollision collide(double m1, double m2, const EmdstarBody &b1, const EmdstarBody &b2,
                             Fallback f = Fallback::None) const {
        EmdstarCollision c;
        check(emdstar_pair_collide(p_, m1, m2, &b1, &b2, static_cast<int>(f), &c));
        return c;
    }
    EmdstarCollision collide_wall(const EmdstarBody &b, const double normal[3],
                                  Fallback f = Fallback::None) const {
        EmdstarCollision c;
        check(emdstar_pair_collide_wall(p_, &b, normal, static_cast<int>(f), &c));
        return c;
    }
    std::uint64_t fallbacks() const noexcept { return emdstar_pair_fallbacks(p_); }

private:
    explicit Pair(EmdstarPair *p) : p_(p) {
        if (!p_) throw Error(EMDSTAR_STATUS_INVALID_INPUT, emdstar_table_last_error());
    }
    EmdstarPair *p_;
};

}  // namespace emdstar
