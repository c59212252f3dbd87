#include "engine/cvode_solver.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <vector>

#include <cvode/cvode.h>
#include <fmt/format.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include "engine/numerical_error.h"

namespace mb {

namespace {

std::string FlagName(int flag) {
  char* name = CVodeGetReturnFlagName(flag);
  std::string out = name ? name : fmt::format("flag {}", flag);
  std::free(name);
  return out;
}

void Check(int flag, const char* function) {
  if (flag < 0) throw std::runtime_error(fmt::format("CVODE: {} failed: {}", function, FlagName(flag)));
}

}  // namespace

struct CvodeSolver::Impl {
  OdeSystem* system = nullptr;
  SolverSpec spec;
  SUNContext context = nullptr;
  N_Vector y = nullptr;
  SUNMatrix matrix = nullptr;
  SUNLinearSolver linear_solver = nullptr;
  void* memory = nullptr;
  bool initialised = false;
  double t = 0.0;
  std::string callback_error;  // an exception caught in a callback, rethrown after CVode returns
  std::string non_finite;      // the last right-hand side with NaN/Inf, described by the system
  std::vector<int> roots_found;  // CVodeGetRootInfo after a root return
  int last_root = -1;
  mutable SolverStats stats;
  long steps_before_reinit = 0;  // CVodeReInit resets CVODE's own step counter

  // extern "C"-compatible trampolines: never let an exception cross into C.
  static int Rhs(sunrealtype t, N_Vector y, N_Vector ydot, void* user_data) {
    auto* self = static_cast<Impl*>(user_data);
    try {
      self->system->Derivatives(t, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot));
      ++self->stats.rhs_evaluations;
      const double* dx = N_VGetArrayPointer(ydot);
      const double* x = N_VGetArrayPointer(y);
      const int n = self->system->num_states();
      if (std::all_of(dx, dx + n, [](double v) { return std::isfinite(v); })) return 0;
      // Recoverable: CVODE retries with a smaller step; if it still fails, this names the culprit.
      const std::string where = self->system->DescribeNonFinite(x);
      self->non_finite = fmt::format("at t = {:.9g} s: {}", t, where.empty() ? "a derivative is NaN/Inf" : where);
      return 1;
    } catch (const std::exception& e) {
      self->callback_error = e.what();
      return -1;
    }
  }
  static int RootFn(sunrealtype t, N_Vector y, sunrealtype* g, void* user_data) {
    auto* self = static_cast<Impl*>(user_data);
    try {
      self->system->Roots(t, N_VGetArrayPointer(y), g);
      ++self->stats.root_evaluations;
      return 0;
    } catch (const std::exception& e) {
      self->callback_error = e.what();
      return -1;
    }
  }

  ~Impl() {
    if (memory) CVodeFree(&memory);
    if (linear_solver) SUNLinSolFree(linear_solver);
    if (matrix) SUNMatDestroy(matrix);
    if (y) N_VDestroy(y);
    if (context) SUNContext_Free(&context);
  }
};

CvodeSolver::CvodeSolver(OdeSystem* system, const SolverSpec& spec) : impl_(std::make_unique<Impl>()) {
  impl_->system = system;
  impl_->spec = spec;
  const auto n = static_cast<sunindextype>(system->num_states());
  if (n == 0) throw std::invalid_argument("CVODE needs at least one continuous state");
  Check(SUNContext_Create(nullptr, &impl_->context), "SUNContext_Create");
  impl_->y = N_VNew_Serial(n, impl_->context);
  if (!impl_->y) throw std::runtime_error("CVODE: N_VNew_Serial failed (out of memory?)");
  N_VConst(0.0, impl_->y);
  impl_->memory = CVodeCreate(spec.method == "adams" ? CV_ADAMS : CV_BDF, impl_->context);
  if (!impl_->memory) throw std::runtime_error("CVODE: CVodeCreate failed");
}

CvodeSolver::~CvodeSolver() = default;

void CvodeSolver::Reset(double t, const double* x) {
  Impl& s = *impl_;
  double* data = N_VGetArrayPointer(s.y);
  std::copy(x, x + s.system->num_states(), data);
  s.t = t;
  if (!s.initialised) {
    Check(CVodeInit(s.memory, &Impl::Rhs, t, s.y), "CVodeInit");
    Check(CVodeSetUserData(s.memory, &s), "CVodeSetUserData");
    Check(CVodeSStolerances(s.memory, s.spec.rtol, s.spec.atol), "CVodeSStolerances");
    s.matrix = SUNDenseMatrix(s.system->num_states(), s.system->num_states(), s.context);
    s.linear_solver = SUNLinSol_Dense(s.y, s.matrix, s.context);
    if (!s.matrix || !s.linear_solver) throw std::runtime_error("CVODE: dense matrix/linear solver creation failed");
    Check(CVodeSetLinearSolver(s.memory, s.linear_solver, s.matrix), "CVodeSetLinearSolver");
    Check(CVodeSetMaxNumSteps(s.memory, 100000), "CVodeSetMaxNumSteps");
    if (s.spec.max_step > 0.0) Check(CVodeSetMaxStep(s.memory, s.spec.max_step), "CVodeSetMaxStep");
    if (s.system->num_roots() > 0) {
      Check(CVodeRootInit(s.memory, s.system->num_roots(), &Impl::RootFn), "CVodeRootInit");
      Check(CVodeSetNoInactiveRootWarn(s.memory), "CVodeSetNoInactiveRootWarn");
    }
    s.initialised = true;
  } else {
    long steps = 0;
    if (CVodeGetNumSteps(s.memory, &steps) == CV_SUCCESS) s.steps_before_reinit += steps;
    Check(CVodeReInit(s.memory, t, s.y), "CVodeReInit");
  }
  ++s.stats.reinitialisations;
}

double CvodeSolver::Integrate(double t_stop, double* x, bool* root_found) {
  Impl& s = *impl_;
  *root_found = false;
  if (t_stop > s.t) {
    // SUNDIALS 6 has no CVodeClearStopTime: set a fresh stop time before every call.
    Check(CVodeSetStopTime(s.memory, t_stop), "CVodeSetStopTime");
    sunrealtype t_reached = s.t;
    s.callback_error.clear();
    s.non_finite.clear();
    const int flag = CVode(s.memory, t_stop, s.y, &t_reached, CV_NORMAL);
    if (flag < 0) {
      std::string detail = s.callback_error.empty() ? "" : " (in a block: " + s.callback_error + ")";
      // Name the state with the largest weighted local error: where to look for stiffness or a bad model.
      N_Vector weights = N_VClone(s.y), errors = N_VClone(s.y);
      if (CVodeGetErrWeights(s.memory, weights) == CV_SUCCESS && CVodeGetEstLocalErrors(s.memory, errors) == CV_SUCCESS) {
        const double* w = N_VGetArrayPointer(weights);
        const double* e = N_VGetArrayPointer(errors);
        int worst = 0;
        for (int i = 1; i < s.system->num_states(); ++i) {
          if (std::abs(w[i] * e[i]) > std::abs(w[worst] * e[worst])) worst = i;
        }
        detail += fmt::format("; largest weighted local error in continuous state #{}", worst);
      }
      N_VDestroy(weights);
      N_VDestroy(errors);
      if (!s.non_finite.empty()) detail += "; NaN/Inf " + s.non_finite;
      if (!s.callback_error.empty()) {
        throw std::runtime_error(fmt::format("CVODE failed at t = {:.9g} s: {}{}", t_reached, FlagName(flag), detail));
      }
      throw NumericalError(fmt::format("CVODE failed at t = {:.9g} s: {}{}. Try a smaller rtol/maxStep, the bdf "
                                       "method, or check the model for a discontinuity without a zero crossing",
                                       t_reached, FlagName(flag), detail));
    }
    *root_found = flag == CV_ROOT_RETURN;
    s.last_root = -1;
    if (*root_found) {
      ++s.stats.roots_found;
      s.roots_found.assign(static_cast<std::size_t>(s.system->num_roots()), 0);
      if (CVodeGetRootInfo(s.memory, s.roots_found.data()) == CV_SUCCESS) {
        const auto it = std::find_if(s.roots_found.begin(), s.roots_found.end(), [](int r) { return r != 0; });
        if (it != s.roots_found.end()) s.last_root = static_cast<int>(it - s.roots_found.begin());
      }
    }
    s.t = t_reached;
  }
  const double* data = N_VGetArrayPointer(s.y);
  std::copy(data, data + s.system->num_states(), x);
  return s.t;
}

int CvodeSolver::last_root() const { return impl_->last_root; }

const SolverStats& CvodeSolver::stats() const {
  long steps = 0;
  if (impl_->initialised && CVodeGetNumSteps(impl_->memory, &steps) == CV_SUCCESS) {
    impl_->stats.steps = impl_->steps_before_reinit + steps;
  }
  return impl_->stats;
}

}  // namespace mb
