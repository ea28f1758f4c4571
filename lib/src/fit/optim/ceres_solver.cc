// The Ceres back end: our own thin extern "C" wrapper (the stock ceres/c_api.h has no
// options, bounds, threads or summary, and prints). The only C++ file of the library.
//
// Shape of the Ceres problem: one parameter block of npar doubles and one residual
// block of npar + 1 residuals that stands for all nres residuals of the problem.
//
// Compression. Fits are tall and thin (millions of residuals, a few parameters): Ceres'
// own work on an n x p Jacobian (copies, scaling, J'J, model residuals) would cost
// several times the evaluation, and the Jacobian alone is 200 MB for a MERL table. So
// the problem's fused pass (bf_problem_normal: sum r^2, J'r and J'J in one sweep, no
// Jacobian stored) is handed to Ceres as p + 1 residuals: with J'J = F'F (F from the
// eigen-decomposition of the Jacobi-scaled J'J) and F'z = J'r, the residuals are
// [z; sqrt(|r|^2 - |z|^2)] with Jacobian [F; 0]. Cost |r|^2, gradient J'r,
// Gauss-Newton matrix J'J and the model cost change r'J d + |J d|^2 / 2 are then all
// exactly those of the full problem, so every Ceres step is the one the uncompressed
// problem would take (the conditioning is that of the normal equations, as with Ceres'
// default dense_normal_cholesky). Residual-only evaluations (step acceptance needs only
// the cost) return [|r|; 0].
//
// Threads: the fused pass runs on the requested threads over fixed chunks summed in
// order, so a solve gives the same bits for every thread count; Ceres itself runs on one.
//
// Robust losses are applied per residual by the fused pass (bf_loss_residual in
// solve.h: g = sign(r) sqrt(rho(r^2))), not with ceres::LossFunction, which would apply
// rho to the squared norm of the whole block.

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <new>
#include <string>
#include <utility>
#include <vector>

#include <ceres/ceres.h>
#include <ceres/manifold.h>
#include <Eigen/Dense>
#include <glog/logging.h>

#include "brdfit/solve.h"
#include "backends.h"

namespace
{

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// The whole problem as one compressed Ceres cost function (see the top of the file).
// One instance serves every active-set round of a solve, so the point a round ends at
// is not evaluated again when the next one starts or when its gradient is checked.
class NormalCost final : public ceres::CostFunction
{
  public:
    NormalCost(const bf_problem *p, const bf_loss &loss, int threads) : p_(p), loss_(loss), threads_(threads)
    {
        set_num_residuals(p->npar + 1);
        mutable_parameter_block_sizes()->push_back(p->npar);
    }

    bool Evaluate(double const *const *parameters, double *residuals, double **jacobians) const override
    {
        const size_t np = static_cast<size_t>(p_->npar);
        if (!update(parameters[0]))
            return false;
        if (jacobians && jacobians[0]) {
            std::copy(cache_g_.begin(), cache_g_.end(), residuals);
            std::copy(cache_F_.begin(), cache_F_.end(), jacobians[0]);
        } else { // the cost alone: exactly |r|^2 / 2 as well
            std::fill(residuals, residuals + np + 1, 0.0);
            residuals[0] = std::sqrt(cache_ssq_);
        }
        return true;
    }

    // The cost's gradient sum g dg/dx at x; false if x cannot be evaluated.
    bool gradient(const double *x, std::vector<double> &grad) const
    {
        if (!update(x))
            return false;
        grad = cache_jtr_;
        return true;
    }

    int passes() const { return passes_; }

  private:
    // The fused pass at x unless it is the last point evaluated (Ceres asks again at the
    // same point at every iteration). Every pass computes the Jacobian's sums too: Ceres
    // asks for them at almost every point whose cost it asks for (the line search of a
    // bounded step, or the Jacobian once a step is accepted), and one pass with them
    // costs less than two passes. Ceres evaluates the one block from one thread at a
    // time, so the cache needs no lock.
    bool update(const double *x) const
    {
        const size_t np = static_cast<size_t>(p_->npar);
        if (cache_state_ != kEmpty && std::equal(cache_x_.begin(), cache_x_.end(), x))
            return cache_state_ == kValid;
        ++passes_;
        cache_state_ = kInvalid;
        cache_x_.assign(x, x + np);
        double ssq = 0.0;
        cache_jtr_.assign(np, 0.0);
        std::vector<double> jtj(np * np);
        if (bf_problem_normal(p_, x, &loss_, threads_, &ssq, cache_jtr_.data(), jtj.data()) != 0)
            return false; // out of memory: Ceres treats the point as invalid
        cache_g_.assign(np + 1, 0.0);
        cache_F_.assign((np + 1) * np, 0.0);
        cache_ssq_ = ssq;
        if (compress(ssq, jtj.data(), cache_jtr_.data(), cache_g_.data(), cache_F_.data()))
            cache_state_ = kValid;
        return cache_state_ == kValid;
    }

    // [z; sqrt(|r|^2 - |z|^2)] (g, np + 1) and [F; 0] (F, (np + 1) x np, row-major)
    // from |r|^2, J'J (a, np x np) and J'r (b). False for non-finite input (a NaN or Inf
    // residual or Jacobian entry reaches |r|^2 or the diagonal of J'J).
    bool compress(double rr, const double *a, const double *b, double *gout, double *fout) const
    {
        const Eigen::Index np = p_->npar;
        Eigen::Map<Eigen::VectorXd> g(gout, np + 1);
        Eigen::Map<RowMatrix> F(fout, np + 1, np);
        if (!std::isfinite(rr))
            return false;
        const Eigen::Map<const RowMatrix> A(a, np, np);
        if (!A.diagonal().allFinite())
            return false;
        // Jacobi scaling first, so that a parameter whose column is tiny next to the
        // others is not taken for a null direction.
        Eigen::VectorXd d(np);
        for (Eigen::Index k = 0; k < np; k++)
            d[k] = A(k, k) > 0.0 ? 1.0 / std::sqrt(A(k, k)) : 0.0;
        const Eigen::MatrixXd As = d.asDiagonal() * A * d.asDiagonal();
        if (!As.allFinite())
            return false;
        Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(As);
        if (es.info() != Eigen::Success)
            return false;
        const Eigen::VectorXd &lam = es.eigenvalues();
        const Eigen::MatrixXd &V = es.eigenvectors();
        const Eigen::VectorXd db = d.cwiseProduct(Eigen::Map<const Eigen::VectorXd>(b, np));
        const double tol =
            std::max(lam.maxCoeff(), 0.0) * static_cast<double>(np) * std::numeric_limits<double>::epsilon();
        double zz = 0.0;
        for (Eigen::Index j = 0; j < np; j++) {
            if (!(lam[j] > tol))
                continue; // (numerically) null: no step information
            const double s = std::sqrt(lam[j]);
            for (Eigen::Index k = 0; k < np; k++)
                F(j, k) = d[k] > 0.0 ? s * V(k, j) / d[k] : 0.0;
            g[j] = V.col(j).dot(db) / s;
            zz += g[j] * g[j];
        }
        g[np] = std::sqrt(std::max(0.0, rr - zz));
        return g.allFinite() && F.allFinite();
    }

    const bf_problem *p_;
    bf_loss loss_;
    int threads_;
    mutable int passes_ = 0;
    enum CacheState { kEmpty, kValid, kInvalid };
    mutable CacheState cache_state_ = kEmpty;
    mutable std::vector<double> cache_x_, cache_g_, cache_F_, cache_jtr_;
    mutable double cache_ssq_ = 0.0;
};

struct NamedAlgorithm {
    const char *name;
    ceres::TrustRegionStrategyType type;
    const char *as_run;
};
// Ceres' strategy for each Ceres method of the registry (methods.c).
const NamedAlgorithm kAlgorithms[] = {
    {"lm", ceres::LEVENBERG_MARQUARDT, "levenberg_marquardt"},
    {"dogleg", ceres::DOGLEG, "dogleg"},
};

struct NamedSolver {
    const char *name;
    ceres::LinearSolverType type;
};
// The solvers that make sense for one dense parameter block (the Schur solvers need
// several blocks to eliminate).
const NamedSolver kLinearSolvers[] = {
    {"dense_normal_cholesky", ceres::DENSE_NORMAL_CHOLESKY},
    {"dense_qr", ceres::DENSE_QR},
    {"sparse_normal_cholesky", ceres::SPARSE_NORMAL_CHOLESKY},
    {"cgnr", ceres::CGNR},
};

bool sparse_available()
{
    return ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::SUITE_SPARSE) ||
           ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::CX_SPARSE) ||
           ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::EIGEN_SPARSE) ||
           ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::ACCELERATE_SPARSE);
}

std::string known_linear_solvers()
{
    std::string s;
    for (const NamedSolver &n : kLinearSolvers) {
        if (n.type == ceres::SPARSE_NORMAL_CHOLESKY && !sparse_available())
            continue;
        if (!s.empty())
            s += ", ";
        s += n.name;
    }
    return s;
}

// One line: newlines and tabs of Ceres' messages become spaces.
void copy_line(char *dst, size_t cap, const std::string &src)
{
    size_t n = std::min(cap - 1, src.size());
    for (size_t i = 0; i < n; i++) {
        const char c = src[i];
        dst[i] = (c == '\n' || c == '\r' || c == '\t') ? ' ' : c;
    }
    dst[n] = '\0';
}

bool all_finite(const double *x, int n)
{
    for (int i = 0; i < n; i++)
        if (!std::isfinite(x[i]))
            return false;
    return true;
}

// Bounds. Ceres handles a bound only by projecting each step onto the box: when the
// optimum has a parameter on its bound and that parameter is coupled to others, the
// projected Gauss-Newton steps are wrong for the free parameters, the trust region
// shrinks at every step and the solve crawls. So bounds get an active set around Ceres
// (a primal active-set method): a round ends early once free parameters have sat on
// their bounds for kStallIterations iterations, and they are then held there
// (SubsetManifold) for the next round; when a round converges, a held parameter whose
// gradient points into the box is released and one on its bound whose gradient points
// out is held, until the held set satisfies the KKT sign conditions.
constexpr int kStallIterations = 3;

// Slow progress. A model with a direction the data hardly determine (two lobes where one
// would do, a weight against a shape parameter) has a long curved valley, along which
// Levenberg-Marquardt takes many small successful steps, each lowering the cost by about
// the function tolerance: dozens of passes for a change in the error far below its
// sampling noise. A round ends as converged when the cost fell by less than
// kSlowRelative (relative) over the last kSlowWindow successful steps.
constexpr int kSlowWindow = 5;
constexpr double kSlowRelative = 1e-8;

// Watches a round: ends it on a stall at a bound (kBound) or on slow progress (kSlow), and
// aborts it when the caller cancels (kCancel: the cancel flag, or the progress callback,
// which sees the solve's iterations counted over every round).
class RoundWatch final : public ceres::IterationCallback
{
  public:
    enum Reason { kNone, kBound, kSlow, kCancel };
    RoundWatch(const double *x, const std::vector<double> &lo, const std::vector<double> &hi,
               const std::vector<char> &held, const bf_solver_options *o, int iterations_before, bool stall = true)
        : x_(x), lo_(lo), hi_(hi), held_(held), o_(o), before_(iterations_before), stall_(stall)
    {
    }
    ceres::CallbackReturnType operator()(const ceres::IterationSummary &it) override
    {
        if (bf_solver_cancelled(o_, before_ + it.iteration, it.cost)) {
            reason_ = kCancel;
            return ceres::SOLVER_ABORT;
        }
        bool on_bound = false;
        for (size_t k = 0; k < held_.size(); k++)
            if (!held_[k] && (x_[k] == lo_[k] || x_[k] == hi_[k]))
                on_bound = true;
        streak_ = on_bound ? streak_ + 1 : 0;
        if (stall_ && streak_ >= kStallIterations) {
            reason_ = kBound;
            return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
        }
        if (it.iteration == 0 || it.step_is_successful)
            costs_.push_back(it.cost);
        const size_t n = costs_.size();
        if (n > static_cast<size_t>(kSlowWindow) &&
            costs_[n - 1 - kSlowWindow] - costs_[n - 1] <= kSlowRelative * costs_[n - 1]) {
            reason_ = kSlow;
            return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
        }
        return ceres::SOLVER_CONTINUE;
    }
    Reason reason() const { return reason_; }

  private:
    const double *x_;
    const std::vector<double> &lo_, &hi_;
    const std::vector<char> &held_;
    const bf_solver_options *o_;
    int before_;
    bool stall_;
    int streak_ = 0;
    std::vector<double> costs_;
    Reason reason_ = kNone;
};

// Ceres warns through glog (linear solver failures, thread counts, failed evaluations)
// even with logging_type SILENT, and before InitGoogleLogging glog writes to stderr.
// The library prints nothing, so unless the host program has set glog up itself (then
// it chose where logs go), only fatal messages are let through.
void silence_glog()
{
    static std::once_flag once;
    std::call_once(once, [] {
        if (!google::IsGoogleLoggingInitialized())
            FLAGS_minloglevel = std::max<int>(FLAGS_minloglevel, google::GLOG_FATAL);
    });
}

// One solve, shared by its phases (check_options, set_bounds, configure_options,
// start_active_set, the rounds, copy_out_summary): the problem and options, Ceres'
// settings, the bounds, and the active-set rounds so far (see RoundWatch).
struct SolveState {
    SolveState(const bf_problem *problem, const bf_solver_options *options, double *start)
        : p(problem), o(options), x(start), np(problem->npar)
    {
    }
    const bf_problem *p;
    const bf_solver_options *o;
    double *x;
    const int np;
    const NamedAlgorithm *alg = &kAlgorithms[0];
    const NamedSolver *lin = &kLinearSolvers[0];
    ceres::Solver::Options opt;
    int max_iterations = 0, threads = 1;
    std::vector<double> lo, hi;
    NormalCost *cost = nullptr;
    std::vector<char> user_held, held;
    std::vector<std::vector<char>> seen; // the held sets rounds started with: no cycling
    std::vector<double> best;
    bool have_result = false;
    int rounds = 0, iterations = 0;
    double seconds = 0.0, initial_cost = 0.0, final_cost = 0.0;
    ceres::Solver::Summary sum;
    bool last_round = false; // after a cycle: one round that no stall ends (one_round)
    bool cancelled = false, failed = false;
};

// Options first, so a bad name fails before any work (the registry, methods.c).
bf_status check_options(SolveState &sv, bf_error *err)
{
    const bf_solver_options *o = sv.o;
    bf_solver_options chk = *o;
    chk.backend = BF_BACKEND_CERES;
    if (bf_status rc = bf_solver_options_check(&chk, err); rc != BF_OK)
        return rc;
    const bf_method_info *method = bf_method_find(BF_BACKEND_CERES, o->algorithm);
    for (const NamedAlgorithm &a : kAlgorithms)
        if (std::strcmp(method->name, a.name) == 0)
            sv.alg = &a;
    if (o->linear_solver && *o->linear_solver) {
        sv.lin = nullptr;
        for (const NamedSolver &n : kLinearSolvers)
            if (std::strcmp(o->linear_solver, n.name) == 0)
                sv.lin = &n;
        if (!sv.lin || (sv.lin->type == ceres::SPARSE_NORMAL_CHOLESKY && !sparse_available()))
            return bf_fail(err, BF_ERR_ARG, "unknown Ceres linear solver '%s' (known: %s)", o->linear_solver,
                           known_linear_solvers().c_str());
    }
    if (o->loss.kind != BF_LOSS_NONE && !(o->loss.scale > 0.0 && std::isfinite(o->loss.scale)))
        return bf_fail(err, BF_ERR_ARG, "loss scale must be positive and finite (got %g)", o->loss.scale);
    if (o->max_iterations < 0 || o->function_tolerance < 0 || o->gradient_tolerance < 0 || o->parameter_tolerance < 0 ||
        o->max_seconds < 0 || o->threads < 0)
        return bf_fail(err, BF_ERR_ARG, "Ceres solver limits and tolerances must not be negative");
    return BF_OK;
}

// Bounds and a feasible, finite start (Ceres requires lo <= x <= hi).
bf_status set_bounds(SolveState &sv, bf_error *err)
{
    const double inf = std::numeric_limits<double>::infinity();
    const bf_problem *p = sv.p;
    sv.lo.assign(sv.np, -inf);
    sv.hi.assign(sv.np, inf);
    for (int k = 0; k < sv.np; k++) {
        if (p->lo)
            sv.lo[k] = p->lo[k];
        if (p->hi)
            sv.hi[k] = p->hi[k];
        if (std::isnan(sv.lo[k]) || std::isnan(sv.hi[k]) || sv.lo[k] > sv.hi[k])
            return bf_fail(err, BF_ERR_RANGE, "parameter %d has invalid bounds [%g, %g]", k, sv.lo[k], sv.hi[k]);
        if (!std::isfinite(sv.x[k]))
            return bf_fail(err, BF_ERR_RANGE, "start value of parameter %d is not finite", k);
    }
    return BF_OK;
}

// Ceres' settings from the options, checked as Ceres would check them.
bf_status configure_options(SolveState &sv, bf_error *err)
{
    const bf_solver_options *o = sv.o;
    ceres::Solver::Options &opt = sv.opt;
    opt.minimizer_type = ceres::TRUST_REGION;
    opt.trust_region_strategy_type = sv.alg->type;
    opt.linear_solver_type = sv.lin->type;
    sv.max_iterations = o->max_iterations > 0 ? o->max_iterations : 100;
    opt.function_tolerance = o->function_tolerance > 0 ? o->function_tolerance : 1e-10;
    opt.gradient_tolerance = o->gradient_tolerance > 0 ? o->gradient_tolerance : 1e-12;
    opt.parameter_tolerance = o->parameter_tolerance > 0 ? o->parameter_tolerance : 1e-10;
    opt.num_threads = 1; // the fused pass has the threads (see the top of the file)
    sv.threads = std::max(1, o->threads);
    // Silence: no progress table, no glog lines from the minimizer.
    opt.minimizer_progress_to_stdout = false;
    opt.logging_type = ceres::SILENT;
    std::string why;
    if (!opt.IsValid(&why)) // checked here: Solve would log it
        return bf_fail(err, BF_ERR_ARG, "invalid Ceres options: %s", why.c_str());
    silence_glog();
    return BF_OK;
}

// The start clamped into the box, and the first round's held set.
void start_active_set(SolveState &sv)
{
    double *x = sv.x;
    for (int k = 0; k < sv.np; k++)
        x[k] = std::min(std::max(x[k], sv.lo[k]), sv.hi[k]);
    sv.user_held.assign(sv.np, 0);
    sv.held.assign(sv.np, 0);
    for (int k = 0; k < sv.np; k++)
        sv.user_held[k] = sv.held[k] = sv.o->constant && sv.o->constant[k];
    // A start on a bound (a previous solve's answer, as the fit's presolve hands over) is
    // taken as active from the start; the KKT check releases it if that was wrong.
    for (int k = 0; k < sv.np; k++)
        if (x[k] == sv.lo[k] || x[k] == sv.hi[k])
            sv.held[k] = 1;
    sv.best.assign(x, x + sv.np);
}

// One Ceres solve from x with the parameters flagged in `held` constant.
void run_ceres(SolveState &sv)
{
    const int np = sv.np;
    double *x = sv.x;
    ceres::Problem::Options po;
    po.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP; // it lives for every round
    ceres::Problem problem(po);                                // owns the manifold
    problem.AddResidualBlock(sv.cost, nullptr, x);
    std::vector<int> fixed;
    for (int k = 0; k < np; k++) {
        if (sv.held[k]) {
            fixed.push_back(k);
            continue; // a held parameter needs no bounds (and Ceres clamps none)
        }
        if (std::isfinite(sv.lo[k]))
            problem.SetParameterLowerBound(x, k, sv.lo[k]);
        if (std::isfinite(sv.hi[k]))
            problem.SetParameterUpperBound(x, k, sv.hi[k]);
    }
    if (static_cast<int>(fixed.size()) == np)
        problem.SetParameterBlockConstant(x);
    else if (!fixed.empty())
        problem.SetManifold(x, new ceres::SubsetManifold(np, fixed));
    ceres::Solve(sv.opt, &problem, &sv.sum);
}

// One round under its watcher, counted into the solve's rounds, iterations and seconds;
// why the watcher ended it.
RoundWatch::Reason run_round(SolveState &sv)
{
    sv.seen.push_back(sv.held);
    RoundWatch watcher(sv.x, sv.lo, sv.hi, sv.held, sv.o, sv.iterations, !sv.last_round);
    sv.opt.callbacks.clear();
    sv.opt.update_state_every_iteration = true;
    sv.opt.callbacks.push_back(&watcher);
    sv.sum = ceres::Solver::Summary();
    run_ceres(sv);
    sv.rounds++;
    sv.iterations += sv.sum.iterations.empty() ? 0 : static_cast<int>(sv.sum.iterations.size() - 1);
    sv.seconds += std::max(0.0, sv.sum.total_time_in_seconds);
    if (sv.rounds == 1)
        sv.initial_cost = sv.sum.initial_cost;
    return watcher.reason();
}

// Cancelled: the round's last accepted point, if it is one, else the best so far.
void keep_cancelled(SolveState &sv)
{
    sv.cancelled = true;
    if (std::isfinite(sv.sum.final_cost) && all_finite(sv.x, sv.np) &&
        (!sv.have_result || sv.sum.final_cost <= sv.final_cost)) {
        sv.best.assign(sv.x, sv.x + sv.np);
        sv.final_cost = sv.sum.final_cost;
        sv.have_result = true;
    }
    std::copy(sv.best.begin(), sv.best.end(), sv.x);
}

// The round's point as the best so far, unless the round failed: false then, with the
// best point back in x.
bool accept_round(SolveState &sv)
{
    const ceres::Solver::Summary &sum = sv.sum;
    const bool ended = sum.termination_type == ceres::CONVERGENCE || sum.termination_type == ceres::NO_CONVERGENCE ||
                       sum.termination_type == ceres::USER_SUCCESS;
    if (!ended || !std::isfinite(sum.final_cost) || !all_finite(sv.x, sv.np)) {
        std::copy(sv.best.begin(), sv.best.end(), sv.x); // never hand out a failed point
        sv.failed = !sv.have_result;
        return false;
    }
    sv.best.assign(sv.x, sv.x + sv.np);
    sv.final_cost = sum.final_cost;
    sv.have_result = true;
    return true;
}

// The held set for the next round into next (the current one on entry); false when the
// rounds are done.
bool next_active_set(SolveState &sv, std::vector<char> &next)
{
    const double *x = sv.x;
    const int np = sv.np;
    if (sv.sum.termination_type == ceres::USER_SUCCESS) {
        // Stopped on a stall: hold what sits on its bound.
        for (int k = 0; k < np; k++)
            if (x[k] == sv.lo[k] || x[k] == sv.hi[k])
                next[k] = 1;
        return true;
    }
    // Converged (or out of iterations): the KKT signs, where anything touches a
    // bound.
    bool touching = false;
    for (int k = 0; k < np; k++)
        touching = touching || (!sv.user_held[k] && (sv.held[k] || x[k] == sv.lo[k] || x[k] == sv.hi[k]));
    if (!touching || sv.sum.termination_type != ceres::CONVERGENCE)
        return false;
    std::vector<double> grad;
    if (!sv.cost->gradient(x, grad))
        return false;
    for (int k = 0; k < np; k++)
        if (!sv.user_held[k])
            next[k] = (x[k] == sv.lo[k] && grad[k] > 0.0) || (x[k] == sv.hi[k] && grad[k] < 0.0);
    return next != sv.held; // the same set: a consistent active set, done
}

// One active-set round and the held set that follows from it; false when the rounds
// are over.
bool one_round(SolveState &sv)
{
    const bf_solver_options *o = sv.o;
    ceres::Solver::Summary &sum = sv.sum;
    sv.opt.max_num_iterations = sv.max_iterations - sv.iterations;
    sv.opt.max_solver_time_in_seconds = o->max_seconds > 0 ? o->max_seconds - sv.seconds : 1e9;
    if (sv.have_result && (sv.opt.max_num_iterations <= 0 || sv.opt.max_solver_time_in_seconds <= 0))
        return false;
    const RoundWatch::Reason reason = run_round(sv);
    if (reason == RoundWatch::kCancel) {
        keep_cancelled(sv);
        return false;
    }
    if (!accept_round(sv))
        return false;
    std::vector<char> next(sv.held);
    const bool slow = sum.termination_type == ceres::USER_SUCCESS && reason == RoundWatch::kSlow;
    if (slow) { // converged, for every purpose below
        sum.termination_type = ceres::CONVERGENCE;
        char why[96];
        snprintf(why, sizeof why, "cost decreased by less than %g (relative) over the last %d steps", kSlowRelative,
                 kSlowWindow);
        sum.message = why;
    }
    if (!next_active_set(sv, next))
        return false;
    // A set tried already would go round in circles (a parameter that the gradient
    // lets go and the steps bring back): the rounds end, each round having only
    // lowered the cost. When a stall ended the round, it ended before converging:
    // one last round holds what sits on its bounds and runs to convergence (a
    // parameter that reaches a bound there stays on it, projected).
    if (sv.last_round || std::find(sv.seen.begin(), sv.seen.end(), next) != sv.seen.end()) {
        if (sv.last_round || sum.termination_type != ceres::USER_SUCCESS)
            return false;
        sv.last_round = true;
    }
    sv.held.swap(next);
    return true;
}

// The rounds' outcome into s: costs, counts, the termination text and why it stopped.
void copy_out_summary(const SolveState &sv, bf_solution *s)
{
    const double inf = std::numeric_limits<double>::infinity();
    const ceres::Solver::Summary &sum = sv.sum;
    const bf_solver_options *o = sv.o;
    double *x = sv.x;
    const int np = sv.np;
    // No usable round: the cost is unknown (Ceres says -1), which must not look like
    // the best cost of a multistart.
    const bool start_cost = sv.rounds > 0 && std::isfinite(sum.initial_cost) && sum.initial_cost >= 0;
    s->initial_cost = sv.have_result ? sv.initial_cost : start_cost ? sum.initial_cost : inf;
    s->final_cost = sv.have_result ? sv.final_cost : s->initial_cost;
    s->iterations = sv.iterations;
    s->evaluations = sv.cost->passes();
    s->seconds = sv.seconds;
    copy_line(s->algorithm, sizeof s->algorithm, sv.alg->as_run);
    std::string type = sv.cancelled ? "CANCELLED"
                       : sum.termination_type == ceres::USER_SUCCESS
                           ? "NO_CONVERGENCE" // only when the limits ended the rounds
                           : ceres::TerminationTypeToString(sum.termination_type);
    if (sv.rounds > 1)
        type += " (" + std::to_string(sv.rounds) + " active-set rounds)";
    copy_line(s->termination, sizeof s->termination,
              sv.cancelled ? type + ": by the caller after " + std::to_string(sv.iterations) + " iterations"
                           : type + ": " + sum.message);
    s->usable = sv.have_result && std::isfinite(s->final_cost) && all_finite(x, np);
    // Why it stopped: the limits show as NO_CONVERGENCE (or a round stopped on a stall
    // when they ended the rounds); which limit, from the counts.
    if (sv.cancelled)
        s->stop = BF_STOP_CANCELLED;
    else if (sv.failed || !s->usable || sum.termination_type == ceres::FAILURE)
        s->stop = BF_STOP_FAILED;
    else if (sum.termination_type == ceres::CONVERGENCE)
        s->stop = BF_STOP_CONVERGED;
    else
        s->stop = o->max_seconds > 0 && sv.seconds >= o->max_seconds ? BF_STOP_TIME : BF_STOP_ITERATIONS;
    if (!s->usable && !all_finite(x, np))
        std::copy(sv.best.begin(), sv.best.end(), x);
}

bf_status solve(const bf_problem *p, const bf_solver_options *o, double *x, bf_solution *s, bf_error *err)
{
    SolveState sv(p, o, x);
    bf_status rc = check_options(sv, err);
    if (rc == BF_OK)
        rc = set_bounds(sv, err);
    if (rc == BF_OK)
        rc = configure_options(sv, err);
    if (rc != BF_OK)
        return rc;
    start_active_set(sv);
    // Active-set rounds (see RoundWatch); the iteration and time limits are shared.
    NormalCost cost(p, o->loss, sv.threads);
    sv.cost = &cost;
    for (const int max_rounds = 2 * sv.np + 2; sv.rounds < max_rounds;)
        if (!one_round(sv))
            break;
    copy_out_summary(sv, s);
    return BF_OK;
}

} // namespace

extern "C" bf_status bf_solve_ceres(const bf_problem *p, const bf_solver_options *o, double *x, bf_solution *s,
                                    bf_error *err)
{
    if (!p || !o || !x || !s)
        return bf_fail(err, BF_ERR_ARG, "bf_solve_ceres: problem, options, x and solution are required");
    std::memset(s, 0, sizeof *s);
    copy_line(s->backend, sizeof s->backend, "ceres");
    copy_line(s->algorithm, sizeof s->algorithm, "levenberg_marquardt");
    if (!p->eval || p->npar <= 0 || p->nres == 0)
        return bf_fail(err, BF_ERR_ARG,
                       "Ceres problem needs an eval function, parameters and residuals (npar %d, nres %zu)", p->npar,
                       p->nres);
    if (p->nres > static_cast<size_t>(std::numeric_limits<int>::max()))
        return bf_fail(err, BF_ERR_RANGE, "Ceres problem has too many residuals (%zu)", p->nres);
    try {
        return solve(p, o, x, s, err);
    } catch (const std::bad_alloc &) {
        return bf_fail(err, BF_ERR_NOMEM, "Ceres solve: out of memory (%zu residuals)", p->nres);
    } catch (const std::exception &e) {
        return bf_fail(err, BF_ERR_ARG, "Ceres solve failed: %s", e.what());
    }
}
