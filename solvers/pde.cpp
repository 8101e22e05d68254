#include "sdmesh/pde.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <functional>
#include <string>

#include <omp.h>

#include "sdmesh/error.hpp"
#include "sdmesh/geometry.hpp"

#include "constant_modes.hpp"
#include "explained_factor.hpp"
#include "free_vertices.hpp"
#include "number_text.hpp"

namespace sdmesh {
namespace {

using Sparse = Eigen::SparseMatrix<double>;

void check_vector(const Eigen::VectorXd& x, Eigen::Index size, const char* who, const char* what) {
    if (x.size() != size)
        throw InvalidArgumentError(std::string(who) + ": " + what + " has " + std::to_string(x.size()) +
                                   " entries, expected " + std::to_string(size));
    // A NaN would spread through the solve and come out as a NaN solution without an error.
    for (Eigen::Index i = 0; i < size; ++i)
        if (!std::isfinite(x[i]))
            throw InvalidArgumentError(std::string(who) + ": " + what + " has a non-finite entry at " +
                                       std::to_string(i) + " (" + detail::number_text(x[i]) + ")");
}

void check_time_step(double t, const char* who) {
    if (!(t > 0) || !std::isfinite(t))
        throw InvalidArgumentError(std::string(who) + ": the time step must be positive and finite, got " +
                                   detail::number_text(t));
}

// Far above the squared edge lengths (~ trace(M) / trace(L)), t·L swamps M in M + tL: relative to
// L, M then only survives to about ε·ratio, and from 1e12 on (an error of ~1e-4 in the heat that
// M alone conserves) the solutions are mostly rounding. On the bunny at 1e-80 (ratio 3e158) the
// factorization failed; at ratio 1e31 it passed and the heat came out 1e-14 times too small.
void check_time_scale(const Sparse& L, const Sparse& M, double t) {
    constexpr double kMaxRatio = 1e12;
    const double ratio = t * L.diagonal().sum() / M.diagonal().sum();
    if (ratio > kMaxRatio) {
        char message[256];
        std::snprintf(message, sizeof message,
                      "heat: the time step t = %g is %.3g times the squared edge length (trace(M)/trace(L)); beyond "
                      "%.0e, M + tL loses M to rounding: take a smaller t",
                      t, ratio, kMaxRatio);
        throw InvalidArgumentError(message);
    }
}

// A vertex in no face has neither mass nor stiffness: unless it is pinned, M + tL is singular in
// its row, and Cholesky would only name a column.
void check_no_free_isolated_vertex(const Sparse& L, const Sparse& M, const std::vector<int>& pinned) {
    const Eigen::VectorXd mass = M.diagonal(), stiffness = L.diagonal();
    std::vector<char> is_pinned(static_cast<size_t>(mass.size()), 0);
    for (const int v : pinned)
        if (v >= 0 && v < mass.size()) is_pinned[static_cast<size_t>(v)] = 1;
    for (Eigen::Index v = 0; v < mass.size(); ++v)
        if (mass[v] == 0 && stiffness[v] == 0 && !is_pinned[static_cast<size_t>(v)])
            throw NumericalError("heat: vertex " + std::to_string(v) +
                                 " has no mass and no stiffness (a vertex in no face, which sdmesh repair drops)");
}

}  // namespace

// ---- Poisson ---------------------------------------------------------------------------------------

PoissonSolver::PoissonSolver(const Sparse& L, const Sparse& M, const std::vector<int>& dirichlet_vertices,
                             const CholeskyOptions& cholesky) {
    detail::check_operator_pair(L, M, "Poisson");
    const int n = static_cast<int>(L.rows());
    int count = 0;
    component_ = detail::connected_components(L, count);
    neumann_component_.assign(static_cast<size_t>(count), 1);
    for (int v : dirichlet_vertices)  // out-of-range vertices are reported by Pins
        if (v >= 0 && v < n) neumann_component_[static_cast<size_t>(component_[static_cast<size_t>(v)])] = 0;

    // Pin the first vertex of each component without Dirichlet data to 0, which makes L on the
    // free vertices definite; the mean is fixed after the solve.
    fixed_ = dirichlet_vertices;
    std::vector<char> pinned(static_cast<size_t>(count), 0);
    for (int v = 0; v < n; ++v) {
        const auto c = static_cast<size_t>(component_[static_cast<size_t>(v)]);
        if (neumann_component_[c] && !pinned[c]) {
            pinned[c] = 1;
            fixed_.push_back(v);
        }
    }
    const detail::Pins pins(n, fixed_, "Poisson");
    dirichlet_count_ = static_cast<int>(dirichlet_vertices.size());
    coupling_ = pins.coupling(L);

    lumped_mass_ = M * Eigen::VectorXd::Ones(n);
    component_area_ = Eigen::VectorXd::Zero(count);
    for (int v = 0; v < n; ++v) component_area_[component_[static_cast<size_t>(v)]] += lumped_mass_[v];
    // Without area every vertex is isolated and L = 0: any u solves L u = M f, none is "the" solution.
    if (n > 0 && !(component_area_.maxCoeff() > 0))
        throw NumericalError("Poisson: the mass matrix has no positive entry (a mesh without faces?)");
    Sparse A = L;
    pins.apply(A);
    solver_ = detail::explained("Poisson: L on the vertices not pinned", detail::kIndefiniteMeshAdvice,
                                [&] { return CholeskySolver(A, cholesky); });
}

Eigen::VectorXd PoissonSolver::solve(const Eigen::VectorXd& b, const Eigen::VectorXd& dirichlet_values) const {
    const auto n = static_cast<Eigen::Index>(component_.size());
    check_vector(b, n, "Poisson", "the right-hand side");
    if (dirichlet_values.size() != 0) check_vector(dirichlet_values, dirichlet_count_, "Poisson", "dirichlet_values");
    const auto count = static_cast<Eigen::Index>(neumann_component_.size());
    auto neumann = [&](Eigen::Index v) {
        const int c = component_[static_cast<size_t>(v)];
        return neumann_component_[static_cast<size_t>(c)] && component_area_[c] > 0;
    };

    Eigen::VectorXd rhs = b, total = Eigen::VectorXd::Zero(count);
    for (Eigen::Index v = 0; v < n; ++v) total[component_[static_cast<size_t>(v)]] += b[v];
    for (Eigen::Index v = 0; v < n; ++v) {
        const int c = component_[static_cast<size_t>(v)];
        if (neumann(v)) rhs[v] -= total[c] * lumped_mass_[v] / component_area_[c];
    }
    Eigen::VectorXd g = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(fixed_.size()));  // pinned vertices stay 0
    if (dirichlet_values.size() != 0) g.head(dirichlet_count_) = dirichlet_values;
    Eigen::VectorXd u = solver_.solve(detail::pinned_rhs(rhs, fixed_, coupling_, g));

    Eigen::VectorXd mean = Eigen::VectorXd::Zero(count);
    for (Eigen::Index v = 0; v < n; ++v) mean[component_[static_cast<size_t>(v)]] += lumped_mass_[v] * u[v];
    for (Eigen::Index v = 0; v < n; ++v) {
        const int c = component_[static_cast<size_t>(v)];
        if (neumann(v)) u[v] -= mean[c] / component_area_[c];
    }
    return u;
}

// ---- heat --------------------------------------------------------------------------------------------

HeatSolver::HeatSolver(const Sparse& L, const Sparse& M, double t, const std::vector<int>& dirichlet_vertices,
                       const CholeskyOptions& cholesky) {
    detail::check_operator_pair(L, M, "heat");
    check_time_step(t, "heat");
    check_time_scale(L, M, t);
    detail::Pins(static_cast<int>(L.rows()), dirichlet_vertices, "heat");  // checks the vertices
    check_no_free_isolated_vertex(L, M, dirichlet_vertices);
    fixed_ = dirichlet_vertices;
    L_ = L;
    M_ = M;
    const Sparse A = pinned_matrix(t);
    solver_ = detail::explained("heat: M + tL", detail::kIndefiniteMeshAdvice, [&] { return CholeskySolver(A, cholesky); });
}

void HeatSolver::set_time_step(double t) {
    check_time_step(t, "heat");
    check_time_scale(L_, M_, t);
    const Sparse A = pinned_matrix(t);
    detail::explained("heat: M + tL", detail::kIndefiniteMeshAdvice, [&] { solver_.factorize(A); });
}

Sparse HeatSolver::pinned_matrix(double t) {
    const auto n = static_cast<size_t>(L_.rows());
    const detail::ConstantModes modes = detail::constant_modes(L_, M_);
    std::vector<char> held(static_cast<size_t>(modes.count()), 0);  // by a Dirichlet vertex
    for (const int v : fixed_) {
        const int mode = modes.mode_of[static_cast<size_t>(v)];
        if (mode >= 0) held[static_cast<size_t>(mode)] = 1;
    }
    pinned_ = fixed_;
    std::vector<int> diffused_of_mode(static_cast<size_t>(modes.count()), -1);
    std::vector<double> mass;
    for (const int j : modes.lost_shift(L_, 1 / t)) {
        if (held[static_cast<size_t>(j)]) continue;
        pinned_.push_back(modes.first[static_cast<size_t>(j)]);
        if (!(modes.mass[j] > 0)) continue;  // no heat to restore (0 then, as L u = 0 there)
        diffused_of_mode[static_cast<size_t>(j)] = static_cast<int>(mass.size());
        mass.push_back(modes.mass[j]);
    }
    diffused_mass_ = Eigen::Map<const Eigen::VectorXd>(mass.data(), static_cast<Eigen::Index>(mass.size()));
    diffused_of_.clear();
    if (!mass.empty()) {
        diffused_of_.resize(n);
        for (size_t v = 0; v < n; ++v) {
            const int mode = modes.mode_of[v];
            diffused_of_[v] = mode >= 0 ? diffused_of_mode[static_cast<size_t>(mode)] : -1;
        }
    }
    Sparse A = M_ + t * L_;
    detail::Pins(static_cast<int>(n), pinned_, "heat").apply(A);
    return A;
}

void HeatSolver::restore_conserved_heat(const Eigen::VectorXd& b, Eigen::VectorXd& u) const {
    if (diffused_of_.empty()) return;
    const Eigen::VectorXd Mu = M_ * u;
    const auto n = static_cast<Eigen::Index>(diffused_of_.size());
    Eigen::VectorXd missing = Eigen::VectorXd::Zero(diffused_mass_.size());
    for (Eigen::Index v = 0; v < n; ++v)
        if (const int c = diffused_of_[static_cast<size_t>(v)]; c >= 0) missing[c] += b[v] - Mu[v];
    for (Eigen::Index v = 0; v < n; ++v)
        if (const int c = diffused_of_[static_cast<size_t>(v)]; c >= 0) u[v] += missing[c] / diffused_mass_[c];
}

Eigen::VectorXd HeatSolver::step(const Eigen::VectorXd& u0, int steps) const {
    check_vector(u0, L_.cols(), "heat", "u0");
    if (steps < 0) throw InvalidArgumentError("heat: steps must be >= 0, got " + std::to_string(steps));
    Eigen::VectorXd u = u0;
    for (int v : fixed_) u[v] = 0;
    for (int s = 0; s < steps; ++s) {
        const Eigen::VectorXd b = M_ * u;
        u = solver_.solve(detail::pinned_rhs(b, pinned_, Sparse(), Eigen::VectorXd()));
        restore_conserved_heat(b, u);
    }
    return u;
}

// ---- heat-method geodesics ---------------------------------------------------------------------------

namespace {

// The heat time of each component, in units of 2^length_exponent (a time is a squared length):
// options.time, or h² with h the mean edge length of the component (Crane et al. 2013, m = 1).
// One h for the whole mesh is far too long on a component far smaller than the rest: its heat
// is then its mean to within rounding, which leaves no gradient (beside a unit sphere, one 1e-6
// across got distances up to 1.8e-7 for π·1e-6).
Eigen::VectorXd heat_times(const Triangulation& unit, const std::vector<int>& component, int count,
                           int length_exponent, const GeodesicOptions& options) {
    if (!std::isnan(options.time)) {
        check_time_step(options.time, "geodesics");
        return Eigen::VectorXd::Constant(count, std::ldexp(options.time, -2 * length_exponent));
    }
    if (count == 1) return Eigen::VectorXd::Constant(1, unit.length.mean() * unit.length.mean());
    Eigen::VectorXd sum = Eigen::VectorXd::Zero(count), edges = Eigen::VectorXd::Zero(count);
    for (int e = 0; e < unit.num_edges(); ++e) {
        const int c = component[static_cast<size_t>(unit.E(e, 0))];
        sum[c] += unit.length[e];
        edges[c] += 1;
    }
    return (sum.array() / edges.array().max(1)).square();  // no edge (a vertex in no face): 0
}

// The component with the most vertices (the first of them): its heat time is the one reported.
int largest_component(const std::vector<int>& component, int count) {
    std::vector<int> size(static_cast<size_t>(count), 0);
    for (const int c : component) ++size[static_cast<size_t>(c)];
    return static_cast<int>(std::max_element(size.begin(), size.end()) - size.begin());
}

// (T / time) L, T the heat time of each vertex's component: M + time·that is M + TL, and
// symmetric, as L has no entries between components.
Sparse timed_laplacian(const Sparse& L, const std::vector<int>& component, const Eigen::VectorXd& times, double time) {
    Sparse timed = L;
    if (!(time > 0) || (times.array() == time).all()) return timed;  // a time of 0 is refused by name later
    for (int j = 0; j < timed.outerSize(); ++j) {
        const double factor = times[component[static_cast<size_t>(j)]] / time;
        for (Sparse::InnerIterator it(timed, j); it; ++it) it.valueRef() *= factor;
    }
    return timed;
}

std::vector<int> boundary_vertices(const Triangulation& t) {
    std::vector<int> vertices;
    for (int e = 0; e < t.num_edges(); ++e)
        if (t.is_boundary(e)) vertices.insert(vertices.end(), {t.E(e, 0), t.E(e, 1)});
    std::sort(vertices.begin(), vertices.end());
    vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
    return vertices;
}

}  // namespace

HeatGeodesics::UnitLengths HeatGeodesics::unit_lengths(const Triangulation& t) {
    if (t.num_edges() == 0) throw InvalidArgumentError("geodesics: the triangulation has no edges");
    UnitLengths unit{t, std::nullopt, far_unit_exponent(t.length.mean())};
    if (unit.length_exponent != 0) {
        unit.scaled = t;
        for (double& l : unit.scaled->length) l = std::ldexp(l, -unit.length_exponent);
    }
    return unit;
}

HeatGeodesics::HeatGeodesics(const Triangulation& t, const GeodesicOptions& options)
    : HeatGeodesics(unit_lengths(t), options, std::chrono::steady_clock::now()) {}

HeatGeodesics::HeatGeodesics(const UnitLengths& unit, const GeodesicOptions& options,
                             std::chrono::steady_clock::time_point start)
    : HeatGeodesics(unit, options, start, cotan_laplacian(unit.t()), mass_matrix(unit.t(), options.mass)) {}

// Not CHOLMOD's default ordering: on meshes AMD's fill is always high enough that the default
// computes METIS's too and discards AMD's. Coarse nested dissection is ~40 % faster to compute
// than METIS; its ~20 % more fill costs the factorizations little (igea: 6.9 s against 7.9 s
// CPU for ordering and two factorizations). M + tL, L and their pinned forms share L's pattern,
// hence the ordering; the factorizations are independent, so they run side by side.
HeatGeodesics::Factorizations HeatGeodesics::factorize(const Triangulation& t, const GeodesicOptions& options,
                                                       const Sparse& L, const Sparse& timed_L, const Sparse& M,
                                                       double time) {
    std::vector<int> boundary = options.average_boundary_conditions ? boundary_vertices(t) : std::vector<int>{};
    if (boundary.size() == static_cast<size_t>(t.num_vertices)) boundary.clear();
    CholeskySolver ordering;
    ordering.analyze(L, {.ordering = CholeskyOrdering::coarse_nested_dissection});
    const CholeskyOptions shared{.same_ordering_as = &ordering};
    std::optional<HeatSolver> neumann_heat, dirichlet_heat;
    std::optional<PoissonSolver> poisson;
    std::vector<std::function<void()>> tasks = {[&] { neumann_heat.emplace(timed_L, M, time, std::vector<int>{}, shared); },
                                                [&] { poisson.emplace(L, M, std::vector<int>{}, shared); }};
    if (!boundary.empty()) tasks.emplace_back([&] { dirichlet_heat.emplace(timed_L, M, time, boundary, shared); });
    // An exception must not leave an OpenMP region: each task's is kept, the first rethrown.
    std::vector<std::exception_ptr> errors(tasks.size());
    const auto run = [&](int i) {
        try {
            tasks[static_cast<size_t>(i)]();
        } catch (...) {
            errors[static_cast<size_t>(i)] = std::current_exception();
        }
    };
    const int count = static_cast<int>(tasks.size());
    // One thread: no OpenMP region at all. Inside one, even of a single thread, the BLAS calls of
    // the factorizations (OpenBLAS's OpenMP build) ran 6x slower (igea, with CHOLMOD's numeric
    // factorization then: 21-24 s, not 3.6 s).
    if (omp_get_max_threads() > 1) {
#pragma omp parallel for schedule(dynamic, 1)
        for (int i = 0; i < count; ++i) run(i);
    } else {
        for (int i = 0; i < count; ++i) run(i);
    }
    for (const std::exception_ptr& error : errors)
        if (error) std::rethrow_exception(error);
    return {std::move(*neumann_heat), std::move(dirichlet_heat), std::move(*poisson), static_cast<int>(boundary.size())};
}

HeatGeodesics::HeatGeodesics(const UnitLengths& unit, const GeodesicOptions& options,
                             std::chrono::steady_clock::time_point start, const Sparse& L, const Sparse& M)
    : num_vertices_(unit.t().num_vertices),
      length_exponent_(unit.length_exponent),
      divergence_(divergence(unit.t())),
      component_(detail::connected_components(L, component_count_)),
      component_time_(heat_times(unit.t(), component_, component_count_, unit.length_exponent, options)),
      time_(component_time_[largest_component(component_, component_count_)]),
      solvers_(factorize(unit.t(), options, L, timed_laplacian(L, component_, component_time_, time_), M, time_)) {
    report_.boundary_vertices = solvers_.dirichlet_vertices;
    report_.time = std::ldexp(time_, 2 * length_exponent_);
    report_.precompute_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

Eigen::VectorXd HeatGeodesics::distance(const std::vector<int>& sources) const {
    if (sources.empty()) throw InvalidArgumentError("geodesics: no source vertex");
    Eigen::VectorXd u0 = Eigen::VectorXd::Zero(num_vertices_);
    for (int s : sources) {
        if (s < 0 || s >= num_vertices_)
            throw InvalidArgumentError("geodesics: source " + std::to_string(s) + " is out of range [0, " +
                                       std::to_string(num_vertices_) + ")");
        u0[s] = 1;
    }
    Eigen::VectorXd u = solvers_.neumann_heat.step(u0);
    if (solvers_.dirichlet_heat) u = 0.5 * (u + solvers_.dirichlet_heat->step(u0));

    // X = −∇u/|∇u| per face, from divᵀu = −area·∇u; faces where u is flat (to the last bit) get
    // no direction. Far from the sources u is ~1e-240 (igea) and the squares in norm() underflow
    // to 0, which left a third of igea's faces without a direction: so scale by the larger
    // component first (cheaper than hypot).
    Eigen::VectorXd X = divergence_.transpose() * u;
    for (Eigen::Index f = 0; f < X.size() / 2; ++f) {
        auto g = X.segment<2>(2 * f);
        const double scale = std::max(std::abs(g[0]), std::abs(g[1]));
        g = scale > 0 ? Eigen::Vector2d(g / scale).normalized() : Eigen::Vector2d::Zero();
    }
    // ∇φ = X in the weak sense: div ∇φ = −Lφ = div X.
    Eigen::VectorXd phi = solvers_.poisson.solve(-(divergence_ * X));

    // Shift each component so that its sources average 0; +inf where no source is.
    Eigen::VectorXd sum = Eigen::VectorXd::Zero(component_count_), count = Eigen::VectorXd::Zero(component_count_);
    for (int s : sources) {
        sum[component_[static_cast<size_t>(s)]] += phi[s];
        count[component_[static_cast<size_t>(s)]] += 1;
    }
    for (int v = 0; v < num_vertices_; ++v) {
        const int c = component_[static_cast<size_t>(v)];
        phi[v] = count[c] > 0 ? std::ldexp(phi[v] - sum[c] / count[c], length_exponent_)
                              : std::numeric_limits<double>::infinity();
    }
    return phi;
}

Eigen::VectorXd heat_geodesic_distance(const Triangulation& t, const std::vector<int>& sources,
                                       const GeodesicOptions& options) {
    return HeatGeodesics(t, options).distance(sources);
}

}  // namespace sdmesh
