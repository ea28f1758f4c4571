// The Ceres back end: our own thin extern "C" wrapper (the stock ceres/c_api.h has no
// options, bounds, threads or summary, and prints). The only C++ file of the library.
//
// Shape of the Ceres problem: one parameter block of npar doubles, and the nres
// residuals split into B contiguous blocks, each one CostFunction whose Evaluate calls
// problem->eval over its range (our Jacobian layout is Ceres' layout for one parameter
// block).
//
// Block compression. Fits are tall and thin (millions of residuals, a few parameters),
// and Ceres' own work per iteration on an n x p Jacobian (copies, scaling, J'J, model
// residuals) cost about four times the evaluation itself on a MERL-sized problem. So a
// block of n > p + 1 residuals r with Jacobian J hands Ceres p + 1 residuals instead:
// with J'J = F'F (F from the eigen-decomposition of the Jacobi-scaled J'J) and
// F'z = J'r, the block's residuals are [z; sqrt(|r|^2 - |z|^2)] with Jacobian [F; 0].
// Cost |r|^2, gradient J'r, Gauss-Newton matrix J'J and the model cost change
// r'J d + |J d|^2 / 2 are then all exactly those of the full block, so every Ceres
// step is the one the uncompressed problem would take (the conditioning is that of the
// normal equations, as with Ceres' default dense_normal_cholesky). Residual-only
// evaluations (step acceptance needs only the cost) return [|r|; 0].
//
// Robust losses are applied per residual here, not with ceres::LossFunction: Ceres
// applies a loss to the squared norm of a whole residual block, which for our large
// blocks would be rho(sum r^2) instead of sum rho(r^2). Each residual r is replaced by
// g = sign(r) sqrt(rho(r^2)), so that Ceres' cost 1/2 sum g^2 is exactly the robust cost
// 1/2 sum rho(r^2) and its gradient sum rho'(r^2) r dr/dx is exact; the Gauss-Newton
// model of g is a valid (positive semi-definite) robust model. rho uses Ceres' own
// definitions (see solve.h), written so that small residuals keep full precision.

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <cstring>
#include <mutex>
#include <new>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <ceres/ceres.h>
#include <ceres/manifold.h>
#include <Eigen/Dense>
#include <glog/logging.h>

#include "brdfit/solve.h"

namespace {

// Block size: the Jacobian of a block (rows x npar doubles, 512 KB) stays in cache
// between eval writing it and the compression reading it; at least 4 blocks per thread
// so Ceres' dynamic scheduling balances the load. Compressed blocks are p + 1 residuals
// each, so many blocks cost Ceres next to nothing.
constexpr size_t kBlockJacobianDoubles = 65536;
constexpr size_t kMinBlockResiduals = 256;
constexpr size_t kBlocksPerThread = 4;

// rho(s) and rho'(s) as in solve.h (Ceres' definitions), accurate for s -> 0.
double loss_rho(const bf_loss &l, double s, double *d1)
{
    const double a = l.scale;
    switch (l.kind) {
    case BF_LOSS_HUBER:
        if (s <= a * a) {
            *d1 = 1.0;
            return s;
        } else {
            const double r = std::sqrt(s);
            *d1 = a / r;
            return 2.0 * a * r - a * a;
        }
    case BF_LOSS_CAUCHY: {
        const double t = s / (a * a);
        *d1 = 1.0 / (1.0 + t);
        return a * a * std::log1p(t);
    }
    case BF_LOSS_SOFT_L1: {
        // 2 a^2 (sqrt(1 + t) - 1) = 2 s / (sqrt(1 + t) + 1): no cancellation.
        const double q = std::sqrt(1.0 + s / (a * a));
        *d1 = 1.0 / q;
        return 2.0 * s / (q + 1.0);
    }
    case BF_LOSS_ARCTAN: {
        const double t = s / a;
        *d1 = 1.0 / (1.0 + t * t);
        return a * std::atan(t);
    }
    case BF_LOSS_NONE:
    default:
        *d1 = 1.0;
        return s;
    }
}

// Scratch buffers for the uncompressed residuals and Jacobian of a block, shared by
// the threads of one solve: each Evaluate takes one and gives it back.
class ScratchPool {
public:
    struct Buffers {
        std::vector<double> res, jac;
    };
    std::unique_ptr<Buffers> take()
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (free_.empty())
            return std::make_unique<Buffers>();
        std::unique_ptr<Buffers> b = std::move(free_.back());
        free_.pop_back();
        return b;
    }
    void give(std::unique_ptr<Buffers> b)
    {
        std::lock_guard<std::mutex> lock(mutex_);
        free_.push_back(std::move(b));
    }

private:
    std::mutex mutex_;
    std::vector<std::unique_ptr<Buffers>> free_;
};

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// One contiguous range of residuals [r0, r1) as a Ceres cost function (compressed to
// npar + 1 residuals when longer, see the top of the file).
class RangeCost final : public ceres::CostFunction {
public:
    // passes: NULL, or counts the evaluations this block really makes (for the first
    // block: the whole set's evaluations, cached answers not counted).
    RangeCost(const bf_problem *p, const bf_loss &loss, size_t r0, size_t r1, ScratchPool *pool,
              int *passes = nullptr)
        : p_(p), loss_(loss), r0_(r0), r1_(r1), pool_(pool), passes_(passes)
    {
        const size_t np = static_cast<size_t>(p->npar);
        compressed_ = r1 - r0 > np + 1;
        set_num_residuals(static_cast<int>(compressed_ ? np + 1 : r1 - r0));
        mutable_parameter_block_sizes()->push_back(p->npar);
    }

    bool Evaluate(double const *const *parameters, double *residuals,
                  double **jacobians) const override
    {
        double *jac = jacobians ? jacobians[0] : nullptr;
        if (!compressed_) {
            if (passes_)
                ++*passes_;
            return raw(parameters[0], residuals, jac);
        }
        const size_t n = r1_ - r0_, np = static_cast<size_t>(p_->npar);
        const double *x = parameters[0];
        if (cached(x, jac != nullptr)) {
            if (jac) {
                std::copy(cache_g_.begin(), cache_g_.end(), residuals);
                std::copy(cache_F_.begin(), cache_F_.end(), jac);
            } else { // exactly what the residual-only path computes
                std::fill(residuals, residuals + np + 1, 0.0);
                residuals[0] = std::sqrt(cache_rr_);
            }
            return true;
        }
        cache_state_ = kEmpty;
        if (passes_)
            ++*passes_;
        std::unique_ptr<ScratchPool::Buffers> b = pool_->take();
        b->res.resize(n);
        if (jac)
            b->jac.resize(n * np);
        bool ok = raw(x, b->res.data(), jac ? b->jac.data() : nullptr, false);
        double rr = 0.0;
        if (ok)
            ok = compress(b->res.data(), jac ? b->jac.data() : nullptr, residuals, jac, &rr);
        pool_->give(std::move(b));
        if (ok) {
            cache_x_.assign(x, x + np);
            cache_rr_ = rr;
            cache_state_ = jac ? kWithJacobian : kResiduals;
            if (jac) {
                cache_g_.assign(residuals, residuals + np + 1);
                cache_F_.assign(jac, jac + (np + 1) * np);
            }
        }
        return ok;
    }

    // The block's own residuals and Jacobian (loss applied). False when eval fails or
    // gives a non-finite value: Ceres then treats the point as invalid and shrinks the
    // step. check_finite false leaves that test to compress(): a NaN or Inf anywhere in
    // r or in column k of J makes |r|^2 or (J'J)_kk non-finite, which it rejects.
    bool raw(const double *x, double *res, double *jac, bool check_finite = true) const
    {
        if (p_->eval(p_->ctx, x, r0_, r1_, res, jac) != 0)
            return false;
        const size_t n = r1_ - r0_, np = static_cast<size_t>(p_->npar);
        if (check_finite) {
            for (size_t i = 0; i < n; i++)
                if (!std::isfinite(res[i]))
                    return false;
            if (jac)
                for (size_t i = 0; i < n * np; i++)
                    if (!std::isfinite(jac[i]))
                        return false;
        }
        if (loss_.kind != BF_LOSS_NONE)
            apply_loss(res, jac, n, np);
        return true;
    }

private:
    // The last evaluation of this block is reused when Ceres asks again at the same
    // point, which it does at every iteration: a bounded problem's trust-region step is
    // checked by a line search that evaluates the candidate with its gradient, then
    // the candidate's cost is evaluated, then, once accepted, its Jacobian. The answers
    // are the ones a fresh evaluation would give (the same code on the same input).
    // Ceres evaluates a block from one thread at a time, so the cache needs no lock.
    enum CacheState { kEmpty, kResiduals, kWithJacobian };
    bool cached(const double *x, bool want_jacobian) const
    {
        if (cache_state_ == kEmpty || (want_jacobian && cache_state_ != kWithJacobian))
            return false;
        return std::equal(cache_x_.begin(), cache_x_.end(), x);
    }

    // [z; sqrt(|r|^2 - |z|^2)] and [F; 0] from r (n) and J (n x p); J NULL: [|r|; 0].
    // *rr_out: |r|^2.
    bool compress(const double *res, const double *jac, double *out, double *out_jac,
                  double *rr_out) const
    {
        const Eigen::Index n = static_cast<Eigen::Index>(r1_ - r0_), np = p_->npar;
        Eigen::Map<const Eigen::VectorXd> r(res, n);
        Eigen::Map<Eigen::VectorXd> g(out, np + 1);
        const double rr = r.squaredNorm();
        *rr_out = rr;
        g.setZero();
        if (!std::isfinite(rr))
            return false;
        if (!out_jac) {
            g[0] = std::sqrt(rr);
            return std::isfinite(g[0]);
        }
        Eigen::Map<RowMatrix> F(out_jac, np + 1, np);
        F.setZero();
        Eigen::MatrixXd A = Eigen::MatrixXd::Zero(np, np); // J'J
        Eigen::VectorXd b = Eigen::VectorXd::Zero(np);     // J'r
        normal_equations(jac, res, n, np, A.data(), b.data());
        A.triangularView<Eigen::StrictlyUpper>() = A.transpose();
        if (!A.diagonal().allFinite())
            return false;
        // Jacobi scaling first, so that a parameter whose column is tiny next to the
        // others is not taken for a null direction.
        Eigen::VectorXd d(np);
        for (Eigen::Index k = 0; k < np; k++)
            d[k] = A(k, k) > 0.0 ? 1.0 / std::sqrt(A(k, k)) : 0.0;
        const Eigen::MatrixXd As = d.asDiagonal() * A * d.asDiagonal();
        Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(As);
        if (es.info() != Eigen::Success)
            return false;
        const Eigen::VectorXd &lam = es.eigenvalues();
        const Eigen::MatrixXd &V = es.eigenvectors();
        const Eigen::VectorXd db = d.cwiseProduct(b);
        const double tol = std::max(lam.maxCoeff(), 0.0) * static_cast<double>(np) *
                           std::numeric_limits<double>::epsilon();
        double zz = 0.0;
        for (Eigen::Index j = 0; j < np; j++) {
            if (!(lam[j] > tol))
                continue; // (numerically) null in this block: no step information
            const double s = std::sqrt(lam[j]);
            for (Eigen::Index k = 0; k < np; k++)
                F(j, k) = d[k] > 0.0 ? s * V(k, j) / d[k] : 0.0;
            g[j] = V.col(j).dot(db) / s;
            zz += g[j] * g[j];
        }
        g[np] = std::sqrt(std::max(0.0, rr - zz));
        return g.allFinite() && F.allFinite();
    }

    // The lower triangle of J'J (a, column-major np x np, zeroed) and J'r (b, zeroed)
    // for J (n x np, row-major) and r, skipping zero entries: a residual of one channel
    // does not depend on the other channels' colour parameters, so in RGB fits half of
    // every row is zero. NaN and Inf entries are kept (they reach the diagonal).
    static void normal_equations(const double *jac, const double *res, Eigen::Index n,
                                 Eigen::Index np, double *a, double *b)
    {
        std::vector<Eigen::Index> nz(static_cast<size_t>(np));
        for (Eigen::Index i = 0; i < n; i++) {
            const double *row = jac + i * np, ri = res[i];
            Eigen::Index m = 0;
            for (Eigen::Index k = 0; k < np; k++)
                if (row[k] != 0.0)
                    nz[m++] = k;
            for (Eigen::Index u = 0; u < m; u++) {
                const Eigen::Index k = nz[u];
                const double jk = row[k];
                b[k] += jk * ri;
                for (Eigen::Index v = 0; v <= u; v++) // a(k, l), l = nz[v] <= k
                    a[nz[v] * np + k] += jk * row[nz[v]];
            }
        }
    }

    // r -> g = sign(r) sqrt(rho(r^2)); dg/dr = rho'(s) |r| / sqrt(rho(s)) (1 at r = 0).
    void apply_loss(double *res, double *jac, size_t n, size_t np) const
    {
        for (size_t i = 0; i < n; i++) {
            const double r = res[i], s = r * r;
            double d1;
            const double rho = loss_rho(loss_, s, &d1);
            const double g = std::sqrt(rho);
            double dg = 1.0;
            if (g > 0.0) {
                dg = d1 * std::fabs(r) / g;
                res[i] = std::copysign(g, r);
            }
            if (jac)
                for (size_t k = 0; k < np; k++)
                    jac[i * np + k] *= dg;
        }
    }

    const bf_problem *p_;
    bf_loss loss_;
    size_t r0_, r1_;
    ScratchPool *pool_;
    int *passes_;
    bool compressed_;
    mutable CacheState cache_state_ = kEmpty;
    mutable std::vector<double> cache_x_, cache_g_, cache_F_;
    mutable double cache_rr_ = 0.0;
};

struct NamedAlgorithm {
    const char *name;
    ceres::TrustRegionStrategyType type;
    const char *as_run;
};
const NamedAlgorithm kAlgorithms[] = {
    {"lm", ceres::LEVENBERG_MARQUARDT, "levenberg_marquardt"},
    {"levenberg_marquardt", ceres::LEVENBERG_MARQUARDT, "levenberg_marquardt"},
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
// projected Gauss-Newton steps are wrong for the free parameters and the solve crawls
// until a tolerance stops it far from the optimum. So bounds get an active set around
// Ceres: a parameter that sits on its bound with the gradient pushing outwards is held
// there (SubsetManifold) and the rest re-solved, until the held set satisfies the KKT
// sign conditions. A callback ends a round early once a free parameter has stayed on a
// bound for kStallIterations iterations, so the crawl costs a few iterations only.
constexpr int kStallIterations = 3;

class BoundWatch final : public ceres::IterationCallback {
public:
    BoundWatch(const double *x, const std::vector<double> &lo, const std::vector<double> &hi,
               const std::vector<char> &held)
        : x_(x), lo_(lo), hi_(hi), held_(held)
    {
    }
    ceres::CallbackReturnType operator()(const ceres::IterationSummary &) override
    {
        bool on_bound = false;
        for (size_t k = 0; k < held_.size(); k++)
            if (!held_[k] && (x_[k] == lo_[k] || x_[k] == hi_[k]))
                on_bound = true;
        streak_ = on_bound ? streak_ + 1 : 0;
        return streak_ >= kStallIterations ? ceres::SOLVER_TERMINATE_SUCCESSFULLY
                                           : ceres::SOLVER_CONTINUE;
    }

private:
    const double *x_;
    const std::vector<double> &lo_, &hi_;
    const std::vector<char> &held_;
    int streak_ = 0;
};

// Gradient of the cost, sum_i g_i dg_i/dx, over all blocks with up to `threads`
// threads; each thread sums a fixed set of blocks and the partial sums are added in
// thread order, so the result does not depend on scheduling. False if eval fails.
bool cost_gradient(const bf_problem *p, const bf_loss &loss,
                   const std::vector<std::pair<size_t, size_t>> &blocks, int threads,
                   const double *x, std::vector<double> &grad)
{
    const size_t np = static_cast<size_t>(p->npar);
    const int nt = std::max(1, std::min<int>(threads, static_cast<int>(blocks.size())));
    std::vector<std::vector<double>> part(nt, std::vector<double>(np, 0.0));
    std::vector<char> ok(nt, 1);
    auto work = [&](int t) {
        std::vector<double> res, jac;
        for (size_t b = static_cast<size_t>(t); b < blocks.size(); b += nt) {
            const size_t r0 = blocks[b].first, r1 = blocks[b].second, n = r1 - r0;
            res.resize(n);
            jac.resize(n * np);
            RangeCost cost(p, loss, r0, r1, nullptr);
            if (!cost.raw(x, res.data(), jac.data())) {
                ok[t] = 0;
                return;
            }
            for (size_t i = 0; i < n; i++)
                for (size_t k = 0; k < np; k++)
                    part[t][k] += res[i] * jac[i * np + k];
        }
    };
    std::vector<std::thread> pool;
    for (int t = 1; t < nt; t++)
        pool.emplace_back(work, t);
    work(0);
    for (std::thread &th : pool)
        th.join();
    grad.assign(np, 0.0);
    for (int t = 0; t < nt; t++) {
        if (!ok[t])
            return false;
        for (size_t k = 0; k < np; k++)
            grad[k] += part[t][k];
    }
    return true;
}

// One Ceres solve from x with the parameters flagged in `held` constant.
void run_ceres(const bf_problem *p, const bf_loss &loss, const ceres::Solver::Options &opt,
               ScratchPool *pool,
               const std::vector<std::pair<size_t, size_t>> &blocks, const std::vector<double> &lo,
               const std::vector<double> &hi, const std::vector<char> &held, double *x,
               ceres::Solver::Summary *sum, int *passes)
{
    const int np = p->npar;
    ceres::Problem problem; // owns the cost functions and the manifold
    for (size_t b = 0; b < blocks.size(); b++)
        problem.AddResidualBlock(new RangeCost(p, loss, blocks[b].first, blocks[b].second, pool,
                                               b == 0 ? passes : nullptr),
                                 nullptr, x);
    std::vector<int> fixed;
    for (int k = 0; k < np; k++) {
        if (held[k]) {
            fixed.push_back(k);
            continue; // a held parameter needs no bounds (and Ceres clamps none)
        }
        if (std::isfinite(lo[k]))
            problem.SetParameterLowerBound(x, k, lo[k]);
        if (std::isfinite(hi[k]))
            problem.SetParameterUpperBound(x, k, hi[k]);
    }
    if (static_cast<int>(fixed.size()) == np)
        problem.SetParameterBlockConstant(x);
    else if (!fixed.empty())
        problem.SetManifold(x, new ceres::SubsetManifold(np, fixed));
    ceres::Solve(opt, &problem, sum);
}

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

int solve(const bf_problem *p, const bf_solver_options *o, double *x, bf_solution *s,
          bf_error *err)
{
    const int np = p->npar;
    const double inf = std::numeric_limits<double>::infinity();

    // Options first, so a bad name fails before any work.
    const NamedAlgorithm *alg = &kAlgorithms[0];
    if (o->algorithm && *o->algorithm) {
        alg = nullptr;
        for (const NamedAlgorithm &a : kAlgorithms)
            if (std::strcmp(o->algorithm, a.name) == 0)
                alg = &a;
        if (!alg)
            return bf_fail(err, BF_ERR_ARG,
                           "unknown Ceres algorithm '%s' (known: lm, levenberg_marquardt, dogleg)",
                           o->algorithm);
    }
    const NamedSolver *lin = &kLinearSolvers[0];
    if (o->linear_solver && *o->linear_solver) {
        lin = nullptr;
        for (const NamedSolver &n : kLinearSolvers)
            if (std::strcmp(o->linear_solver, n.name) == 0)
                lin = &n;
        if (!lin || (lin->type == ceres::SPARSE_NORMAL_CHOLESKY && !sparse_available()))
            return bf_fail(err, BF_ERR_ARG, "unknown Ceres linear solver '%s' (known: %s)",
                           o->linear_solver, known_linear_solvers().c_str());
    }
    if (o->loss.kind != BF_LOSS_NONE && !(o->loss.scale > 0.0 && std::isfinite(o->loss.scale)))
        return bf_fail(err, BF_ERR_ARG, "loss scale must be positive and finite (got %g)",
                       o->loss.scale);
    if (o->max_iterations < 0 || o->function_tolerance < 0 || o->gradient_tolerance < 0 ||
        o->parameter_tolerance < 0 || o->max_seconds < 0 || o->threads < 0)
        return bf_fail(err, BF_ERR_ARG, "Ceres solver limits and tolerances must not be negative");

    // Bounds and a feasible, finite start (Ceres requires lo <= x <= hi).
    std::vector<double> lo(np, -inf), hi(np, inf);
    for (int k = 0; k < np; k++) {
        if (p->lo)
            lo[k] = p->lo[k];
        if (p->hi)
            hi[k] = p->hi[k];
        if (std::isnan(lo[k]) || std::isnan(hi[k]) || lo[k] > hi[k])
            return bf_fail(err, BF_ERR_RANGE, "parameter %d has invalid bounds [%g, %g]", k,
                           lo[k], hi[k]);
        if (!std::isfinite(x[k]))
            return bf_fail(err, BF_ERR_RANGE, "start value of parameter %d is not finite", k);
    }

    ceres::Solver::Options opt;
    opt.minimizer_type = ceres::TRUST_REGION;
    opt.trust_region_strategy_type = alg->type;
    opt.linear_solver_type = lin->type;
    const int max_iterations = o->max_iterations > 0 ? o->max_iterations : 100;
    opt.function_tolerance = o->function_tolerance > 0 ? o->function_tolerance : 1e-10;
    opt.gradient_tolerance = o->gradient_tolerance > 0 ? o->gradient_tolerance : 1e-12;
    opt.parameter_tolerance = o->parameter_tolerance > 0 ? o->parameter_tolerance : 1e-10;
    opt.num_threads = std::max(1, o->threads);
    // Silence: no progress table, no glog lines from the minimizer.
    opt.minimizer_progress_to_stdout = false;
    opt.logging_type = ceres::SILENT;
    std::string why;
    if (!opt.IsValid(&why)) // checked here: Solve would log it
        return bf_fail(err, BF_ERR_ARG, "invalid Ceres options: %s", why.c_str());
    silence_glog();

    for (int k = 0; k < np; k++)
        x[k] = std::min(std::max(x[k], lo[k]), hi[k]);

    // Blocks: enough for load balance across threads, none larger than the cache-sized
    // block, none empty; residual ranges split as evenly as possible.
    const size_t nres = p->nres;
    const size_t rows = std::max(kMinBlockResiduals, kBlockJacobianDoubles / static_cast<size_t>(np));
    size_t nblocks = std::max(kBlocksPerThread * static_cast<size_t>(opt.num_threads),
                              (nres + rows - 1) / rows);
    nblocks = std::min(nblocks, nres);
    ScratchPool pool;
    std::vector<std::pair<size_t, size_t>> blocks(nblocks);
    for (size_t b = 0; b < nblocks; b++)
        blocks[b] = {nres * b / nblocks, nres * (b + 1) / nblocks};

    // Active-set rounds (see BoundWatch); the iteration and time limits are shared.
    std::vector<char> user_held(np, 0), held(np, 0);
    for (int k = 0; k < np; k++)
        user_held[k] = held[k] = o->constant && o->constant[k];
    std::vector<double> best(x, x + np), grad;
    bool watch = true, have_result = false;
    int rounds = 0, iterations = 0, evaluations = 0;
    double seconds = 0.0, initial_cost = 0.0, final_cost = 0.0;
    ceres::Solver::Summary sum;
    for (const int max_rounds = 2 * np + 2; rounds < max_rounds;) {
        opt.max_num_iterations = max_iterations - iterations;
        opt.max_solver_time_in_seconds = o->max_seconds > 0 ? o->max_seconds - seconds : 1e9;
        if (have_result && (opt.max_num_iterations <= 0 || opt.max_solver_time_in_seconds <= 0))
            break;
        BoundWatch watcher(x, lo, hi, held);
        opt.callbacks.clear();
        opt.update_state_every_iteration = watch;
        if (watch)
            opt.callbacks.push_back(&watcher);
        sum = ceres::Solver::Summary();
        int passes = 0; // Ceres' own counts include the answers served from the cache
        run_ceres(p, o->loss, opt, &pool, blocks, lo, hi, held, x, &sum, &passes);
        rounds++;
        iterations += sum.iterations.empty() ? 0 : static_cast<int>(sum.iterations.size() - 1);
        evaluations += passes;
        seconds += std::max(0.0, sum.total_time_in_seconds);
        if (rounds == 1)
            initial_cost = sum.initial_cost;
        const bool ended = sum.termination_type == ceres::CONVERGENCE ||
                           sum.termination_type == ceres::NO_CONVERGENCE ||
                           sum.termination_type == ceres::USER_SUCCESS;
        if (!ended || !std::isfinite(sum.final_cost) || !all_finite(x, np)) {
            std::copy(best.begin(), best.end(), x); // never hand out a failed point
            break;
        }
        best.assign(x, x + np);
        final_cost = sum.final_cost;
        have_result = true;
        const bool stopped = sum.termination_type == ceres::USER_SUCCESS;

        // KKT check: hold a bound parameter whose gradient points out of the box,
        // release one whose gradient points in. Skipped when nothing touches a bound.
        bool touching = stopped;
        for (int k = 0; k < np; k++)
            touching = touching || (!user_held[k] && (held[k] || x[k] == lo[k] || x[k] == hi[k]));
        if (!touching)
            break;
        if (!cost_gradient(p, o->loss, blocks, opt.num_threads, x, grad))
            break;
        evaluations++;
        std::vector<char> next(user_held);
        for (int k = 0; k < np; k++)
            if (!user_held[k])
                next[k] = (x[k] == lo[k] && grad[k] > 0.0) || (x[k] == hi[k] && grad[k] < 0.0);
        if (next == held) {
            if (!stopped)
                break; // a converged round with a consistent active set: done
            watch = false; // stopped early, yet nothing to hold: finish without the watch
        }
        held.swap(next);
    }

    // No usable round: the cost is unknown (Ceres says -1), which must not look like
    // the best cost of a multistart.
    const bool start_cost = rounds > 0 && std::isfinite(sum.initial_cost) && sum.initial_cost >= 0;
    s->initial_cost = have_result ? initial_cost : start_cost ? sum.initial_cost : inf;
    s->final_cost = have_result ? final_cost : s->initial_cost;
    s->iterations = iterations;
    s->evaluations = evaluations;
    s->seconds = seconds;
    copy_line(s->algorithm, sizeof s->algorithm, alg->as_run);
    std::string type = sum.termination_type == ceres::USER_SUCCESS
                           ? "NO_CONVERGENCE" // only when the limits ended the rounds
                           : ceres::TerminationTypeToString(sum.termination_type);
    if (rounds > 1)
        type += " (" + std::to_string(rounds) + " active-set rounds)";
    copy_line(s->termination, sizeof s->termination, type + ": " + sum.message);
    s->usable = have_result && std::isfinite(s->final_cost) && all_finite(x, np);
    if (!s->usable && !all_finite(x, np))
        std::copy(best.begin(), best.end(), x);
    return BF_OK;
}

} // namespace

extern "C" int bf_solve_ceres(const bf_problem *p, const bf_solver_options *o, double *x,
                              bf_solution *s, bf_error *err)
{
    if (!p || !o || !x || !s)
        return bf_fail(err, BF_ERR_ARG, "bf_solve_ceres: problem, options, x and solution are required");
    std::memset(s, 0, sizeof *s);
    copy_line(s->backend, sizeof s->backend, "ceres");
    copy_line(s->algorithm, sizeof s->algorithm, "levenberg_marquardt");
    if (!p->eval || p->npar <= 0 || p->nres == 0)
        return bf_fail(err, BF_ERR_ARG,
                       "Ceres problem needs an eval function, parameters and residuals (npar %d, nres %zu)",
                       p->npar, p->nres);
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
