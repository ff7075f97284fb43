// SUNDIALS IDA on the system's DAE, with our Jacobian and KLU solver (ida_integrator.h).
#include <base/text.h>
#include <multibody/ida_integrator.h>
#include <multibody/serial_vector_ops.h>

#include <ida/ida.h>
#include <ida/ida_ls.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iomanip>
#include <limits>
#include <sstream>

namespace flextrack::multibody
{
using namespace dealii;

namespace
{
void to_vector(N_Vector v, Vector<double> &out)
{
  const auto n = N_VGetLength(v);
  out.reinit(n, true);
  std::memcpy(out.data(), N_VGetArrayPointer(v), n * sizeof(double));
}

void from_vector(const Vector<double> &in, N_Vector v) { std::memcpy(N_VGetArrayPointer(v), in.data(), in.size() * sizeof(double)); }
} // namespace

struct IdaIntegrator::Sundials
{
  SUNContext context = nullptr;
  void *ida = nullptr;
  N_Vector y = nullptr, yp = nullptr, id = nullptr;
  N_Vector atol = nullptr; ///< absolute tolerances; infinite: not in the Newton test (error_weights)
  N_Vector weights = nullptr, errors = nullptr; ///< for count_step_limiter()
  N_Vector dky0 = nullptr, dky1 = nullptr;       ///< for interpolate(), twice per step
  SUNMatrix matrix = nullptr;
  SUNLinearSolver solver = nullptr;

  ~Sundials()
  {
    if (ida) IDAFree(&ida);
    if (solver) SUNLinSolFreeEmpty(solver);
    if (matrix) SUNMatFreeEmpty(matrix);
    for (N_Vector v : {y, yp, id, atol, weights, errors, dky0, dky1})
      if (v) N_VDestroy(v);
    if (context) SUNContext_Free(&context);
  }
};

/// The C callbacks; user data is the IdaIntegrator.
struct IdaCallbacks
{
  static int residual(realtype t, N_Vector y, N_Vector yp, N_Vector r, void *data)
  {
    auto *self = static_cast<IdaIntegrator *>(data);
    thread_local Vector<double> yy, yyp, F; // kept: a fresh vector is an allocation per call
    to_vector(y, yy);
    to_vector(yp, yyp);
    try
      {
        self->system.residual(t, yy, yyp, F);
      }
    catch (const std::exception &e)
      {
        self->last_message = e.what();
        return 1; // recoverable: IDA cuts the step
      }
    for (unsigned int i = 0; i < F.size(); ++i)
      if (!std::isfinite(F[i])) return 1;
    from_vector(F, r);
    return 0;
  }

  static int jacobian(realtype t, realtype cj, N_Vector y, N_Vector yp, N_Vector, SUNMatrix, void *data, N_Vector,
                      N_Vector, N_Vector)
  {
    auto *self = static_cast<IdaIntegrator *>(data);
    Vector<double> yy, yyp;
    to_vector(y, yy);
    to_vector(yp, yyp);
    try
      {
        self->system.assemble_jacobian(t, cj, yy, yyp);
      }
    catch (const std::exception &e)
      {
        self->last_message = e.what();
        return 1;
      }
    return 0;
  }

  static int roots(realtype t, N_Vector y, N_Vector yp, realtype *g, void *data)
  {
    auto *self = static_cast<IdaIntegrator *>(data);
    Vector<double> yy, yyp;
    to_vector(y, yy);
    to_vector(yp, yyp);
    self->root_function(t, yy, yyp, g);
    return 0;
  }

  /// Error weights 1 / (rtol |y_i| + atol_i) of IDA's error and Newton tests. The multipliers
  /// are not in the error test (IDASetSuppressAlg); with 'Multiplier tolerance = auto' the
  /// joints' multipliers are not in the Newton test either (weight 0): an error d lambda moves
  /// the velocities by h M^-1 B^T d lambda within the same iteration, and the velocities (and,
  /// through q' = T v - Phi_q^T mu, the positions) are tested, so the test on them bounds the
  /// multipliers' error by what the step can use. A fixed tolerance failed where round-off in
  /// the multipliers, which grows as 1 / h, exceeds it: Andrews' mechanism
  /// (prm/bench/andrews_squeezer.prm) at t = 0 at every rtol (IDA's first step there is about
  /// 1e-14 s); a tolerance scaled as (mass x velocity tolerance) / h still failed it at rtol
  /// 1e-10 and 1e-11 (doc/benchmarks.md). The bodies' normalisation multipliers (|p| = 1) keep
  /// the number (1e-2 for 'auto'): untested, a free flexible body's momentum drift at rtol 1e-10
  /// was 1.08e-9 instead of 6.2e-10. The first step after IDAInit / IDAReInit, whose size IDA
  /// has not chosen yet when it asks for the weights, tests no multiplier. Which multipliers are
  /// tested is decided once, in initialize(): an untested one has an infinite atol (weight 0).
  static int error_weights(N_Vector y, N_Vector ewt, void *data)
  {
    auto *self = static_cast<IdaIntegrator *>(data);
    const double *yy = N_VGetArrayPointer(y), *atol = N_VGetArrayPointer(self->sun->atol);
    double *w = N_VGetArrayPointer(ewt);
    const double rtol = self->settings.relative_tolerance;
    long steps = 0;
    IDAGetNumSteps(self->sun->ida, &steps);
    const unsigned int n = N_VGetLength(y), tested = steps > 0 ? n : self->system.n_q() + self->system.n_v();
    for (unsigned int i = 0; i < tested; ++i) w[i] = 1 / (rtol * std::abs(yy[i]) + atol[i]);
    for (unsigned int i = tested; i < n; ++i) w[i] = 0;
    return 0;
  }

  static void error_handler(int, const char *module, const char *function, char *message, void *data)
  {
    static_cast<IdaIntegrator *>(data)->last_message = std::string(module) + "/" + function + ": " + message;
  }

  // The linear solver: setup = KLU factorisation, solve = KLU solve.
  static SUNLinearSolver_Type ls_type(SUNLinearSolver) { return SUNLINEARSOLVER_DIRECT; }
  static SUNLinearSolver_ID ls_id(SUNLinearSolver) { return SUNLINEARSOLVER_CUSTOM; }
  static int ls_setup(SUNLinearSolver ls, SUNMatrix)
  {
    auto *self = static_cast<IdaIntegrator *>(ls->content);
    // The first setup after a Newton convergence failure searches pivots afresh: a refactorisation
    // with the last pivot order may be what failed (jacobian_solver.h). IDA adds its solver's
    // failures to this count when the nonlinear solve returns, so the setup that follows a cut
    // step sees them.
    long fails = 0;
    IDAGetNumNonlinSolvConvFails(self->sun->ida, &fails);
    const bool fresh_pivots = fails != self->newton_failures_at_setup;
    self->newton_failures_at_setup = fails;
    try
      {
        return self->system.factorize(fresh_pivots) ? SUNLS_SUCCESS : SUNLS_LUFACT_FAIL;
      }
    catch (const std::exception &e) // not through SUNDIALS' C code
      {
        self->last_message = e.what();
        return SUNLS_PACKAGE_FAIL_UNREC;
      }
  }
  static int ls_solve(SUNLinearSolver ls, SUNMatrix, N_Vector x, N_Vector b, realtype)
  {
    auto *self = static_cast<IdaIntegrator *>(ls->content);
    try
      {
        self->system.solve(N_VGetArrayPointer(b), N_VGetArrayPointer(x));
      }
    catch (const std::exception &e)
      {
        self->last_message = e.what();
        return SUNLS_PACKAGE_FAIL_UNREC;
      }
    for (sunindextype i = 0; i < N_VGetLength(x); ++i)
      if (!std::isfinite(N_VGetArrayPointer(x)[i])) return SUNLS_PACKAGE_FAIL_REC;
    return SUNLS_SUCCESS;
  }
  static int ls_free(SUNLinearSolver) { return 0; } // freed with the Sundials struct
  static SUNMatrix_ID matrix_id(SUNMatrix) { return SUNMATRIX_CUSTOM; }
  static int matrix_zero(SUNMatrix) { return 0; } // the Jacobian function overwrites everything
};

// ---------------------------------------------------------------------------------------------
// ---------------------------------------------------------------------------------------------
IdaIntegrator::IdaIntegrator(System &s, const IntegratorSettings &settings_)
  : sun(std::make_unique<Sundials>()), system(s), settings(settings_)
{}

IdaIntegrator::~IdaIntegrator() = default;

void IdaIntegrator::initialize(const double t0, const State &y, const State &yp)
{
  sun = std::make_unique<Sundials>();
  system.use_newton_matrix(true); // modified Newton: G without d(Phi_q^T mu)/dq (System)
  const sunindextype n = system.size();
  if (SUNContext_Create(nullptr, &sun->context) != 0) throw SolverError("SUNDIALS: cannot create a context");
  sun->y = N_VNew_Serial(n, sun->context);
  sun->yp = N_VNew_Serial(n, sun->context);
  sun->id = N_VNew_Serial(n, sun->context);
  // Before IDAInit, which clones its working vectors from y (serial_vector_ops.h).
  for (N_Vector v : {sun->y, sun->yp, sun->id}) install_compiled_ops(v);
  from_vector(y, sun->y);
  from_vector(yp, sun->yp);
  Vector<double> id;
  system.differential_components(id);
  from_vector(id, sun->id);
  for (unsigned int i = system.n_q(); i < system.n_q() + system.n_v(); ++i) id[i] = 1; // massless own velocities: v tolerance

  sun->ida = IDACreate(sun->context);
  IDASetErrHandlerFn(sun->ida, IdaCallbacks::error_handler, this);
  IDAInit(sun->ida, IdaCallbacks::residual, t0, sun->y, sun->yp);
  IDASetUserData(sun->ida, this);
  // The multipliers after the positions and velocities: lambda, then mu - the joints' rows first,
  // then the bodies' |p| = 1 rows (System::layout_multipliers). With 'auto' the joints' ones are
  // left out of the Newton test (error_weights).
  sun->atol = N_VClone(sun->y);
  const sunindextype normalisation = system.n_q() + system.n_v() + 2 * system.n_lambda();
  for (sunindextype i = 0; i < n; ++i)
    N_VGetArrayPointer(sun->atol)[i] =
      id[i] != 0                        ? (i < sunindextype(system.n_q()) ? settings.absolute_tolerance
                                                                          : settings.velocity_tolerance_of(i - system.n_q()))
      : settings.automatic_multiplier_tolerance && i < normalisation ? std::numeric_limits<double>::infinity()
                                                                      : settings.multiplier_tolerance;
  IDAWFtolerances(sun->ida, IdaCallbacks::error_weights);
  IDASetId(sun->ida, sun->id);
  IDASetSuppressAlg(sun->ida, SUNTRUE);
  IDASetMaxOrd(sun->ida, settings.max_order);
  IDASetMaxNonlinIters(sun->ida, settings.max_newton_iterations);
  IDASetMaxNumSteps(sun->ida, settings.max_steps);
  if (settings.max_step > 0) IDASetMaxStep(sun->ida, settings.max_step);
  if (settings.initial_step > 0) IDASetInitStep(sun->ida, settings.initial_step);

  sun->matrix = SUNMatNewEmpty(sun->context);
  sun->matrix->ops->getid = IdaCallbacks::matrix_id;
  sun->matrix->ops->zero = IdaCallbacks::matrix_zero;
  sun->solver = SUNLinSolNewEmpty(sun->context);
  sun->solver->content = this;
  sun->solver->ops->gettype = IdaCallbacks::ls_type;
  sun->solver->ops->getid = IdaCallbacks::ls_id;
  sun->solver->ops->setup = IdaCallbacks::ls_setup;
  sun->solver->ops->solve = IdaCallbacks::ls_solve;
  sun->solver->ops->free = IdaCallbacks::ls_free;
  if (IDASetLinearSolver(sun->ida, sun->solver, sun->matrix) != IDALS_SUCCESS)
    throw SolverError("SUNDIALS IDA refused the linear solver: " + last_message);
  IDASetJacFn(sun->ida, IdaCallbacks::jacobian);
  if (n_roots) IDARootInit(sun->ida, n_roots, IdaCallbacks::roots);
  histogram.fill(0);
  limited_by.clear();
  t_now = output_origin = t0;
}

void IdaIntegrator::reinitialize(const double t, const State &y, const State &yp)
{
  Assert(sun->ida, ExcMessage("initialize() first"));
  before_restart = statistics();
  from_vector(y, sun->y);
  from_vector(yp, sun->yp);
  if (IDAReInit(sun->ida, t, sun->y, sun->yp) != IDA_SUCCESS)
    throw SolverError("SUNDIALS IDA could not restart at t = " + std::to_string(t) + " s: " + last_message);
  t_now = t;
}

void IdaIntegrator::set_root_functions(const unsigned int n, RootFunction g)
{
  n_roots = n;
  root_function = std::move(g);
  if (sun->ida) IDARootInit(sun->ida, n_roots, IdaCallbacks::roots);
}

double IdaIntegrator::integrate(const double t_end, const double output_interval, const Observer &output)
{
  Assert(sun->ida, ExcMessage("initialize() first"));
  IDASetStopTime(sun->ida, t_end);
  // A step floor relative to the run (issue 23, item 5): a law or a force that grows without
  // bound made IDA take ever smaller steps, accepted, for minutes. Below 1e-12 of the run the
  // step makes no progress worth its cost; IDA then stops with its error or convergence failure
  // at |h| = hmin, reported by fail() as a collapsed step.
  smallest_step = std::max(0.0, 1e-12 * (t_end - output_origin));
  IDASetMinStep(sun->ida, smallest_step);
  roots.assign(n_roots, 0);
  // Output times t0 + k dt (not a running sum, which leaves 7.009999999999895 for 7.01).
  double next_output = next_output_time(t_now, output_interval, t_end);
  State y, yp;
  long steps_taken = 0;
  double t_window = t_now; // the time at the start of the progress guard's current window
  while (t_now < t_end)
    {
      const double t_begin = t_now;
      realtype t_reached = t_now;
      const int flag = IDASolve(sun->ida, t_end, &t_reached, sun->y, sun->yp, IDA_ONE_STEP);
      if (flag < 0) fail(flag);
      // IDA's own step limit counts within one IDASolve call, and each call here takes one step:
      // 'Maximum steps' is enforced on the whole call of integrate().
      if (++steps_taken > settings.max_steps)
        {
          last_message = "more than 'Maximum steps' = " + std::to_string(settings.max_steps) + " steps";
          fail(IDA_TOO_MUCH_WORK);
        }
      t_now = t_reached;
      // Progress guard: a run that at its recent pace needs far more than 'Maximum steps' stops
      // now, not after minutes of steps that cannot reach the end anyway. The pace is that of the
      // last window of steps, not of the whole run: a flexible body's start-up transient takes
      // many small steps and is over soon (a pace over the whole run stopped the flexible
      // pendulum at rtol 1e-8 after 10 000 steps). Checked from 50 000 steps on, every 10 000,
      // and only when the projection exceeds twice the limit.
      constexpr long window = 10000, first_check = 50000;
      if (steps_taken % window == 0)
        {
          if (steps_taken >= first_check && t_now > t_window)
            {
              const double projected = steps_taken + window * (t_end - t_now) / (t_now - t_window);
              if (projected > 2.0 * settings.max_steps)
                {
                  last_message = "at its pace over the last " + std::to_string(window) + " steps (to t = " +
                                 base::number_text(t_now) + " s, " + std::to_string(steps_taken) +
                                 " steps in all) the run needs about " + base::number_text(projected) +
                                 " steps, more than twice 'Maximum steps' = " + std::to_string(settings.max_steps);
                  fail(IDA_TOO_MUCH_WORK);
                }
            }
          t_window = t_now;
        }
      int order = 0;
      IDAGetLastOrder(sun->ida, &order);
      if (order >= 1 && order <= 5) ++histogram[order];
      count_step_limiter();
      if (step_hook) step_hook(t_begin, t_now);
      const double tiny = 1e-12 * std::max(1.0, std::abs(t_end));
      while (output && next_output <= t_now + tiny)
        {
          interpolate(std::min(next_output, t_now), y, yp);
          output(std::min(next_output, t_now), y, yp);
          if (next_output >= t_end - tiny) break;
          next_output = next_output_time(next_output, output_interval, t_end);
        }
      if (flag == IDA_ROOT_RETURN)
        {
          IDAGetRootInfo(sun->ida, roots.data());
          if (output) // the state where the root was found
            {
              interpolate(t_now, y, yp);
              output(t_now, y, yp);
            }
          return t_now;
        }
      if (flag == IDA_TSTOP_RETURN) break;
    }
  return t_now;
}

void IdaIntegrator::count_step_limiter()
{
  // The unknown with the largest weighted local error of the step just taken: where the error
  // test, and so the step size, is decided. Its count tells a user which body, mode or joint
  // makes a run slow (log and summary.json).
  if (!sun->weights)
    {
      sun->weights = N_VClone(sun->y);
      sun->errors = N_VClone(sun->y);
      limited_by.assign(system.size(), 0);
    }
  IDAGetErrWeights(sun->ida, sun->weights);
  IDAGetEstLocalErrors(sun->ida, sun->errors);
  const double *w = N_VGetArrayPointer(sun->weights), *e = N_VGetArrayPointer(sun->errors),
               *id = N_VGetArrayPointer(sun->id);
  unsigned int worst = 0;
  double largest = -1;
  for (unsigned int i = 0; i < limited_by.size(); ++i)
    if (id[i] != 0 && std::abs(e[i] * w[i]) > largest) largest = std::abs(e[i] * w[i]), worst = i;
  if (largest > 0) ++limited_by[worst];
}

void IdaIntegrator::interpolate(const double t, State &y, State &yp) const
{
  if (!sun->dky0) sun->dky0 = N_VClone(sun->y);
  if (!sun->dky1) sun->dky1 = N_VClone(sun->y);
  IDAGetDky(sun->ida, t, 0, sun->dky0);
  IDAGetDky(sun->ida, t, 1, sun->dky1);
  to_vector(sun->dky0, y);
  to_vector(sun->dky1, yp);
}

void IdaIntegrator::interpolate_state(const double t, State &y) const
{
  if (!sun->dky0) sun->dky0 = N_VClone(sun->y);
  IDAGetDky(sun->ida, t, 0, sun->dky0);
  to_vector(sun->dky0, y);
}

IntegratorStatistics IdaIntegrator::statistics() const
{
  IntegratorStatistics s;
  if (!sun->ida) return s;
  IDAGetNumSteps(sun->ida, &s.steps);
  IDAGetNumErrTestFails(sun->ida, &s.error_test_failures);
  IDAGetNumNonlinSolvIters(sun->ida, &s.nonlinear_iterations);
  // IDA counts every Newton convergence failure of its nonlinear solver, also those that only
  // make it rebuild a stale Jacobian and solve the same step again; the steps that were cut are
  // the step solve failures.
  IDAGetNumStepSolveFails(sun->ida, &s.nonlinear_convergence_failures);
  IDAGetNumNonlinSolvConvFails(sun->ida, &s.newton_restarts);
  // (the solver's count includes the last failure of each cut step)
  s.newton_restarts = std::max(0L, s.newton_restarts - s.nonlinear_convergence_failures);
  IDAGetNumResEvals(sun->ida, &s.residual_evaluations);
  IDAGetNumJacEvals(sun->ida, &s.jacobian_evaluations);
  IDAGetNumLinSolvSetups(sun->ida, &s.factorizations);
  s.condensed_factorizations = system.n_condensed_factorizations(); // over the whole run, restarts included
  s.condensed_unknowns = system.condensed_size();
  IDAGetLastStep(sun->ida, &s.last_step);
  s.order_histogram = histogram;
  s.steps_limited_by = limited_by;
  const IntegratorStatistics &b = before_restart;
  s.steps += b.steps;
  s.error_test_failures += b.error_test_failures;
  s.nonlinear_iterations += b.nonlinear_iterations;
  s.nonlinear_convergence_failures += b.nonlinear_convergence_failures;
  s.newton_restarts += b.newton_restarts;
  s.residual_evaluations += b.residual_evaluations;
  s.jacobian_evaluations += b.jacobian_evaluations;
  s.factorizations += b.factorizations;
  return s;
}

void IdaIntegrator::fail(const int flag) const
{
  double t = t_now, h = 0;
  IDAGetCurrentTime(sun->ida, &t);
  IDAGetCurrentStep(sun->ida, &h);
  // The unknown with the largest weighted local error, and the largest residual component at
  // the last iterate.
  N_Vector w = N_VClone(sun->y), e = N_VClone(sun->y);
  IDAGetErrWeights(sun->ida, w);
  IDAGetEstLocalErrors(sun->ida, e);
  Vector<double> ww, ee, y, yp, F;
  to_vector(w, ww);
  to_vector(e, ee);
  N_VDestroy(w);
  N_VDestroy(e);
  unsigned int worst_error = 0, worst_residual = 0;
  for (unsigned int i = 0; i < ee.size(); ++i)
    if (std::abs(ee[i] * ww[i]) > std::abs(ee[worst_error] * ww[worst_error])) worst_error = i;
  N_Vector yc = nullptr, ypc = nullptr;
  IDAGetCurrentY(sun->ida, &yc);
  IDAGetCurrentYp(sun->ida, &ypc);
  to_vector(yc ? yc : sun->y, y);
  to_vector(ypc ? ypc : sun->yp, yp);
  system.residual(t, y, yp, F);
  for (unsigned int i = 0; i < F.size(); ++i)
    if (!(std::abs(F[i]) <= std::abs(F[worst_residual]))) worst_residual = i;

  std::ostringstream s;
  s << std::setprecision(6) << "the time integration (IDA) failed at t = " << t << " s, step " << std::setprecision(3)
    << h << " s: " << last_message << " (flag " << flag << "). Largest weighted local error: "
    << system.component_name(worst_error) << "; largest residual: " << system.component_name(worst_residual) << " ("
    << F[worst_residual] << "). What to change: ";
  if (std::abs(h) <= 1.01 * smallest_step && flag != IDA_TOO_MUCH_WORK)
    s << "the step size collapsed to 1e-12 of the run: something grows without bound or jumps near that time (a "
         "driver, a load, a spring); check the entries of the joints and forces acting there";
  else if (flag == IDA_TOO_MUCH_WORK)
    s << "raise 'Maximum steps' or shorten the run";
  else if (flag == IDA_TOO_MUCH_ACC)
    s << "loosen the tolerances";
  else
    s << "look for a singular configuration near that time (a joint at a dead point, a driver that "
         "the mechanism cannot follow), or loosen the tolerances / set a smaller 'Maximum step'";
  throw SolverError(s.str());
}
} // namespace flextrack::multibody
