#pragma once
/// Optimisation on a constraint manifold, for any kit: every iterate keeps the equality
/// constraints h(z) = 0 exactly (a trial step is projected back by minimum-norm Gauss-Newton,
/// which tolerates redundant equations), bounds lo ≤ z ≤ hi are an active set, and inequality
/// rows g(z) ≤ 0 join the equalities while they bind. Steps are taken in the null space of
/// the active constraints:
///  - fit(): Levenberg-Marquardt on least-squares residuals r(z) (f = ½‖r‖²), finished by
///    relax() on f where it crawls (large residuals at the minimum);
///  - relax(): Newton on a scalar potential f(z) with the Hessian of the Lagrangian (finite
///    differences of exact gradients), in the eigenbasis of the reduced Hessian: positive
///    curvature gets a Newton step, negative curvature a descent step (and, at a stationary
///    point, an escape step: saddles and maxima are not minima), and directions the potential
///    does not curve along (neutral) get no step unless it slopes along them;
///  - close(): Levenberg-Marquardt on h alone, from an arbitrary point.
/// Dense Eigen throughout (the kits' problems have tens to a few hundred variables), with
/// LAPACK's divide and conquer for the eigenbases of large models (eigenbasis.h).

#include <Eigen/Dense>
#include <chrono>
#include <memory>
#include <optional>
#include <vector>

#include "fabkit/core/stop_clock.h"

namespace fabkit::solvers {

class Eigenbasis;

/// The functions a ManifoldSolver works with, in scaled coordinates z (≈ mm of motion).
/// Rows, in order: the objective (1 row: a potential; more: least-squares residuals), the
/// equalities h(z) = 0, then the inequalities g(z) ≤ 0.
class ManifoldProblem {
 public:
  virtual ~ManifoldProblem() = default;
  virtual int variables() const = 0;
  virtual int objectives() const = 0;
  virtual int equalities() const = 0;
  virtual int inequalities() const = 0;
  /// Values of every row and the row-major Jacobian (rows × variables) at z: every entry is
  /// written (the solver reuses its buffers without clearing them).
  virtual void evaluate(const double* z, double* values, double* jacobian) = 0;
  /// As evaluate(), for differencing the Hessian: of what it fills only the objective rows'
  /// values and the Jacobian rows of the objective, the equalities and the inequalities that
  /// are not flat are read, so a problem may skip the flat rows (left as they were) where they
  /// cost something — contact rows are distance queries between meshes.
  virtual void evaluate_slopes(const double* z, double* values, double* jacobian) {
    evaluate(z, values, jacobian);
  }
  /// The values of every row at z alone, as evaluate() writes them (a trial step is judged by
  /// its values, and its Jacobian is wasted when the step is rejected). The default evaluates
  /// the Jacobian too; a problem whose Jacobian costs something says otherwise.
  virtual void evaluate_values(const double* z, double* values) {
    std::vector<double> jacobian(
        static_cast<std::size_t>((objectives() + equalities() + inequalities()) * variables()));
    evaluate(z, values, jacobian.data());
  }
  /// Whether a point where the equalities hold is really on the manifold the problem means
  /// (equations with spurious solutions, such as minimal orientation residuals that also
  /// vanish at a half turn, say no here).
  virtual bool acceptable(const double* z) {
    (void)z;
    return true;
  }
  /// Whether inequality `i` (0-based) is taken as flat where it binds: its curvature is left
  /// out of the Hessian of the Lagrangian. Contacts between faceted bodies say yes: their
  /// normals jump from face to face, and differencing them gives curvatures that are not
  /// there.
  virtual bool flat_inequality(int i) const {
    (void)i;
    return false;
  }
  /// Two variables the problem depends on only through one combination of them: every row is
  /// the same at z and at z + t·(null_a·e_a + null_b·e_b) for every t (two turns about one
  /// axis, one on each side of a joint). Large models leave these directions out
  /// (ManifoldSolverOptions::fold_gauge_from). Each variable is in one pair at most.
  struct GaugePair {
    int a = 0, b = 0;
    double null_a = 0, null_b = 0;
  };
  virtual std::vector<GaugePair> gauge_pairs() const { return {}; }
  /// The Hessian (variables × variables) at z of the Lagrangian f − Σ λₖ·row(rowsₖ), if the
  /// problem knows it exactly; false to let the solver difference the gradient instead (one
  /// evaluation per variable). Rows are numbered among the constraints: equality e is e,
  /// inequality i is equalities() + i; flat inequalities are never passed.
  virtual bool lagrangian_hessian(const double* z,
                                  const std::vector<int>& rows,
                                  const Eigen::VectorXd& lambda,
                                  Eigen::MatrixXd& hessian) {
    (void)z;
    (void)rows;
    (void)lambda;
    (void)hessian;
    return false;
  }
};

struct ManifoldSolverOptions {
  /// Converged when the slope of the objective along every allowed motion is below this.
  double gradient_tolerance = 1e-9;
  /// Equalities count as satisfied below this (mm, degrees).
  double feasibility_tolerance = 1e-10;
  /// Projection gives up above this after its iterations.
  double projection_tolerance = 1e-7;
  /// Inequality rows within this of binding are treated as active.
  double inequality_margin = 1e-6;
  /// Curvatures within ± this (relative to the largest, and at least neutral_floor) are
  /// neutral: the potential does not change along them.
  double neutral_curvature = 1e-6;
  double neutral_floor = 1e-9;
  /// A neutral direction gets a step only where the potential slopes along it by more than
  /// this: below it the point is at rest to the caller's tolerance, and walking a flat family
  /// on round-off would make the answer depend on it (where the world is, the connect order).
  double neutral_slope = 1e-6;
  /// Longest step (scaled units, ≈ mm or degrees) along neutral directions with a slope, and
  /// of any step: relax() walks, it does not jump.
  double max_step = 50;
  /// relax() also ends once `progress_window` iterations in a row have together lowered the
  /// objective by less than `least_progress` (0: never). For a run that is only the start of
  /// another, which goes on from wherever it ends.
  int progress_window = 0;
  double least_progress = 0;
  /// relax() ending at a minimum returns its last model's curvature there (Result::curvature),
  /// for a caller that judges the point next.
  bool curvature_at_rest = false;
  /// fit() finishes a crawling Levenberg-Marquardt run with Newton's method only while f is
  /// above this: below it the residuals are as small as the caller needs, and a Newton model
  /// of a large problem costs far more than the little it would gain there. 0: always.
  double finish_above = 0;
  /// Escapes from stationary points that are not minima, before giving up.
  int max_escapes = 20;
  /// From this many free coordinates, each gauge pair (ManifoldProblem::gauge_pairs) whose two
  /// variables are both free is one motion: the models leave its null direction out, which
  /// no step moves along anyway, and their eigendecompositions cost the cube of their size
  /// (a 64-hook chain: 63 pairs of 260 coordinates). Below, the models are as they were.
  int fold_gauge_from = 64;
  /// Stop by this deadline (servers, time limits), shared with the rest of the caller's work.
  /// An iteration that would end past it (judged by what the last ones cost) is not started,
  /// and the deadline is called. None: no limit.
  std::shared_ptr<const StopClock> stop;
};

class ManifoldSolver {
 public:
  /// A point with everything the solver needs about it.
  struct Point {
    Eigen::VectorXd z;
    bool valid = true;
    double f = 0;              ///< objective: ½‖r‖² or the potential
    Eigen::VectorXd g;         ///< its gradient
    Eigen::VectorXd r;         ///< least-squares residuals (fit only)
    Eigen::MatrixXd Jr;        ///< their Jacobian
    Eigen::VectorXd h;         ///< equalities, then the binding inequalities
    Eigen::MatrixXd J;         ///< their Jacobian
    std::vector<int> binding;  ///< which inequalities (0-based) are in h, in order
    /// Whether g, Jr and J are filled (a trial step is first evaluated without them).
    bool complete = true;
  };
  /// The motions allowed at a point.
  struct Active {
    std::vector<int> free;  ///< coordinates that may move (off their bounds, or pulled off)
    /// Rows of Point::h kept: every equality, and the binding inequalities the objective
    /// presses against (one it pulls away from is let go: a part resting on another may lift).
    std::vector<int> rows;
    /// Z, an orthonormal basis of the null space of the kept rows on `free`, is Q[:, rank:]
    /// for the Householder Q of the rows' transpose (a handful of reflectors): products with
    /// it are applied reflector by reflector, O(n·rows), and Zᵀ·H·Z costs O(n²·rows), not 2n³.
    /// No rows kept: Z is the identity and rows_qr is empty.
    std::shared_ptr<const Eigen::ColPivHouseholderQR<Eigen::MatrixXd>> rows_qr;
    int rank = 0;
    /// The gauge pairs folded (large models): column r of the fold B is
    /// keep_self·e(slot) + keep_partner·e(partner) on `free` (partner −1: the coordinate
    /// alone), orthonormal. Empty: B is the identity. Z is a basis in B's coordinates, so a
    /// motion on `free` is B·Z·q.
    struct Fold {
      int slot = 0;
      int partner = -1;
      double keep_self = 1, keep_partner = 0;
    };
    std::vector<Fold> fold;
    /// B's columns.
    int folded() const {
      return fold.empty() ? static_cast<int>(free.size()) : static_cast<int>(fold.size());
    }
    /// How many motions are allowed: Z's columns.
    int motions() const { return folded() - (rows_qr ? rank : 0); }
    /// B·Z·q: the motion with coordinates q, on `free`.
    Eigen::VectorXd along(const Eigen::VectorXd& q) const;
    /// B·Z·Q for a matrix of motions' coordinates (one column each).
    Eigen::MatrixXd along(const Eigen::MatrixXd& q) const;
    /// Zᵀ·Bᵀ·v: v (on `free`) in the motions' coordinates.
    Eigen::VectorXd onto(const Eigen::VectorXd& v) const;
    /// B·Z itself (free × motions), formed column by column.
    Eigen::MatrixXd basis() const;
  };
  /// Second-order information at a point: the reduced Hessian of the Lagrangian along the
  /// allowed motions, in its eigenbasis.
  struct Curvature {
    Eigen::VectorXd eigenvalues;  ///< ascending
    /// Columns: the eigenvectors of the neutral curvatures (|eigenvalue| ≤ neutral_threshold),
    /// in the order of their eigenvalues, in z coordinates.
    Eigen::MatrixXd directions;
    double neutral_threshold = 0;  ///< |eigenvalue| below this is neutral
    std::vector<int> free;         ///< coordinates the directions move
    std::vector<int> rows;         ///< the rows of Point::h the motions keep (Active::rows)
    int binding = 0;               ///< how many of them are binding inequalities
  };
  struct Result {
    Eigen::VectorXd z;
    bool converged = true;  ///< stopped by a tolerance, not by the iteration limit
    bool closed = true;     ///< the equalities hold
    bool timed_out = false;
    int iterations = 0;
    int escapes = 0;  ///< relax(): steps away from saddles and maxima
    /// relax() ending at a minimum, with options().curvature_at_rest: the curvature there, as
    /// curvature() finds it (its last model), so that a caller judging the point need not
    /// make it again.
    std::optional<Curvature> curvature;
  };

  ManifoldSolver(ManifoldProblem& problem,
                 Eigen::VectorXd lo,
                 Eigen::VectorXd hi,
                 ManifoldSolverOptions options = {});

  /// Closes the equalities from an arbitrary point inside the bounds. Returns false if they
  /// stay open; `z` holds the closed point otherwise.
  bool close(Eigen::VectorXd& z, int max_iterations);
  /// Least squares on the manifold from z0. A start whose objective is still above `give_up`
  /// after 15 iterations is abandoned (a random start that will not beat the best).
  Result fit(const Eigen::VectorXd& z0,
             int max_iterations,
             double give_up = std::numeric_limits<double>::infinity());
  /// Minimises the potential on the manifold from z0.
  Result relax(const Eigen::VectorXd& z0, int max_iterations);

  // ---- the pieces, for verdicts built on top (stability tests, second-order checks) --------
  /// Everything at z. The binding inequalities are those within the margin, or exactly
  /// `binding` when given (derivatives by differences need the same rows at every point).
  Point evaluate(const Eigen::VectorXd& z, const std::vector<int>* binding = nullptr);
  /// As evaluate(), with the problem's evaluate_slopes(): the flat inequalities' rows and the
  /// constraint values are not to be read.
  Point evaluate_slopes(const Eigen::VectorXd& z, const std::vector<int>& binding);
  /// Coordinates at a bound stay there unless the objective, after the constraints take their
  /// share, pulls them back inside.
  Active active_set(const Point& p) const;
  /// Coordinates not at a bound.
  std::vector<int> off_bounds(const Point& p) const;
  /// -1 at the lower bound, +1 at the upper, 0 inside.
  int at_bound(const Eigen::VectorXd& z, int k) const;
  /// Hessian of f − λᵀh on the free coordinates (finite differences of exact gradients).
  Eigen::MatrixXd lagrangian_hessian(const Point& p, const Active& act);
  /// (BZ)ᵀ·m·(BZ) for the allowed motions' basis BZ (m itself when it is the identity).
  static Eigen::MatrixXd reduced(const Active& act, const Eigen::MatrixXd& m);
  /// m·B·Z (m itself when BZ is the identity).
  static Eigen::MatrixXd along_motions(const Active& act, const Eigen::MatrixXd& m);
  /// Minimum-norm Gauss-Newton back onto h = 0, moving only coordinates off their bounds; p
  /// may come back without its derivatives (complete() adds them).
  bool project(Point& p);
  /// The curvature of the potential along the allowed motions at p (empty when the deadline
  /// passes before it is known).
  Curvature curvature(const Point& p);
  const Eigen::VectorXd& lower() const { return lo_; }
  const Eigen::VectorXd& upper() const { return hi_; }

  static Eigen::MatrixXd columns(const Eigen::MatrixXd& m, const std::vector<int>& cols);
  static Eigen::VectorXd rows(const Eigen::VectorXd& v, const std::vector<int>& idx);
  /// Orthonormal basis of the null space of m; all of Rⁿ if m has no rows.
  static Eigen::MatrixXd null_space(const Eigen::MatrixXd& m);
  /// Minimum-norm solution of a·x = b where a's rows are independent or consistently
  /// redundant (a fixed joint's closure rows), from a column-pivoted QR of aᵀ with
  /// null_space()'s rank test: a third of the cost of a complete orthogonal decomposition of
  /// a, which the projection back onto the constraints used at every Gauss-Newton iteration.
  static Eigen::VectorXd min_norm_solution(const Eigen::MatrixXd& a, const Eigen::VectorXd& b);
  /// The multipliers λ of rows J (on the free coordinates) for gradient g: the minimum-norm
  /// least-squares solution of Jᵀλ = g, with singular values below 1e-9 of the largest
  /// dropped (redundant rows would otherwise get multipliers as large as round-off is small).
  static Eigen::VectorXd least_squares_multipliers(const Eigen::MatrixXd& rows,
                                                   const Eigen::VectorXd& gradient);

 private:
  Point evaluate_rows(const Eigen::VectorXd& z, const std::vector<int>* binding, bool slopes_only);
  /// f, r and h at z without their derivatives (Point::complete false).
  Point evaluate_values(const Eigen::VectorXd& z);
  /// p's f, r, h and binding from the values just evaluated (`binding` given: those
  /// inequalities; otherwise those within the margin), as both evaluations keep them; the rows
  /// of the values h holds, in order.
  std::vector<int> take_values(Point& p, const std::vector<int>* binding) const;
  /// p with its derivatives, evaluated at p.z if it has none yet.
  void complete(Point& p);
  bool out_of_time() const;
  /// Whether an iteration costing about `cost` would end past the deadline (if so, it is
  /// called: out_of_time() holds from then on).
  bool no_time_for(std::chrono::steady_clock::duration cost) const;
  Point step(const Point& from, const Active& act, const Eigen::VectorXd& dF);
  /// The fold of act.free (large models) and the basis of the motions `kept_rows` (the kept
  /// constraint rows on act.free) allow.
  void set_basis(const Eigen::MatrixXd& kept_rows, Active& act) const;
  /// Ends a Newton run once `window` iterations in a row have together lowered the objective
  /// by less than `least` (window 0: never).
  struct ProgressFloor {
    int window = 0;
    double least = 0;
  };
  /// relax(); with `small_curvatures`, curvatures below the neutral threshold keep their value
  /// where the objective slopes along them (fit()'s Newton finish) instead of counting as 0.
  Result newton(const Eigen::VectorXd& z0,
                int max_iterations,
                bool small_curvatures,
                ProgressFloor floor);
  Eigen::VectorXd multipliers(const Point& p,
                              const std::vector<int>& free,
                              const std::vector<int>& kept) const;
  static std::vector<int> all_rows(const Point& p);
  Result finish(const Point& cur, int iterations, int max_iterations, Result out) const;
  /// The curvature at p from its model's eigendecomposition: every eigenvalue, and the
  /// directions of the neutral ones.
  Curvature curvature_from(const Point& p, const Active& act, const Eigenbasis& eig) const;

  ManifoldProblem& problem_;
  int n_;
  Eigen::VectorXd lo_, hi_;
  ManifoldSolverOptions options_;
  /// The problem's gauge pairs, asked for when a model first is large enough to fold them.
  mutable std::optional<std::vector<ManifoldProblem::GaugePair>> gauge_;
  std::vector<double> values_, jacobian_;
};

}  // namespace fabkit::solvers
