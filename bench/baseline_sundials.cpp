// Peer baseline: the paper's impact-oscillator protocol with SUNDIALS (Debian's
// libsundials-dev 6.4), each integrator with its own root finding:
//   --method cvode-adams: CVODE, variable-order Adams-Moulton with fixed-point iteration
//     (the non-stiff choice), CVodeRootInit;
//   --method arkode-erk: ARKODE's ERKStep with the Dormand-Prince 5(4) table, ERKStepRootInit.
// Impacts stop the solver at the root (direction: y - sigma decreasing); the reset state
// restarts it (ReInit). The section (v decreasing through 0) is a second, non-stopping root.
//
// Build: g++ -O3 -march=native -std=c++20 -DNDEBUG bench/baseline_sundials.cpp -o build/baseline_sundials
//        -lsundials_cvode -lsundials_arkode -lsundials_nvecserial -lsundials_sunnonlinsolfixedpoint
// Run:   build/baseline_sundials --method cvode-adams|arkode-erk [common options, bench/baseline_common.hpp]
#include <arkode/arkode_erkstep.h>
#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include <memory>

#include "baseline_common.hpp"

namespace {

using namespace baseline;

struct context {
    const problem* p;
    double delta2, alpha, M;
    long rhs_calls = 0;
};

int rhs(sunrealtype, N_Vector X, N_Vector dX, void* user)
{
    auto* c = static_cast<context*>(user);
    ++c->rhs_calls;
    const double* x = N_VGetArrayPointer(X);
    double* d = N_VGetArrayPointer(dX);
    const double a = -c->delta2 * x[0] - c->alpha * x[1] + c->M * x[2];
    d[0] = x[1];
    d[1] = a;
    d[2] = x[3];
    d[3] = -x[2] - eps * (x[2] * x[2] - 1.0) * x[3] + A * a;
    return 0;
}

int roots(sunrealtype, N_Vector X, sunrealtype* g, void* user)
{
    const auto* c = static_cast<context*>(user);
    const double* x = N_VGetArrayPointer(X);
    g[0] = x[0] - c->p->sigma;  // impact
    g[1] = x[1];                // section: maxima of y
    return 0;
}

// One integrator behind four calls: the loop below is the same for both.
struct solver {
    virtual ~solver() = default;
    virtual int evolve(double tout, N_Vector y, double* t) = 0;  // 0 step end, 1 root
    virtual void roots_found(int* r) = 0;
    virtual void restart(double t, N_Vector y) = 0;
    virtual void count(long& steps, long& rejected) = 0;  // since the last restart
};

struct cvode_adams : solver {
    void* mem;
    SUNNonlinearSolver nls;
    cvode_adams(SUNContext ctx, context& c, N_Vector y)
    {
        mem = CVodeCreate(CV_ADAMS, ctx);
        CVodeInit(mem, rhs, 0.0, y);
        CVodeSStolerances(mem, c.p->tol, c.p->tol);
        CVodeSetUserData(mem, &c);
        nls = SUNNonlinSol_FixedPoint(y, 0, ctx);
        CVodeSetNonlinearSolver(mem, nls);
        CVodeSetMaxNumSteps(mem, 100000000);
        CVodeRootInit(mem, 2, roots);
        int dirs[2] = {-1, -1};
        CVodeSetRootDirection(mem, dirs);
    }
    ~cvode_adams() override
    {
        CVodeFree(&mem);
        SUNNonlinSolFree(nls);
    }
    int evolve(double tout, N_Vector y, double* t) override
    {
        const int f = CVode(mem, tout, y, t, CV_NORMAL);
        if (f < 0) std::exit(3);
        return f == CV_ROOT_RETURN;
    }
    void roots_found(int* r) override { CVodeGetRootInfo(mem, r); }
    void restart(double t, N_Vector y) override { CVodeReInit(mem, t, y); }
    void count(long& steps, long& rejected) override
    {
        long s = 0, e = 0;
        CVodeGetNumSteps(mem, &s);
        CVodeGetNumErrTestFails(mem, &e);
        steps += s;
        rejected += e;
    }
};

struct arkode_erk : solver {
    void* mem;
    arkode_erk(SUNContext ctx, context& c, N_Vector y)
    {
        mem = ERKStepCreate(rhs, 0.0, y, ctx);
        ERKStepSetTableNum(mem, ARKODE_DORMAND_PRINCE_7_4_5);
        ERKStepSStolerances(mem, c.p->tol, c.p->tol);
        ERKStepSetUserData(mem, &c);
        ERKStepSetMaxNumSteps(mem, 100000000);
        ERKStepRootInit(mem, 2, roots);
        int dirs[2] = {-1, -1};
        ERKStepSetRootDirection(mem, dirs);
    }
    ~arkode_erk() override { ERKStepFree(&mem); }
    int evolve(double tout, N_Vector y, double* t) override
    {
        const int f = ERKStepEvolve(mem, tout, y, t, ARK_NORMAL);
        if (f < 0) std::exit(3);
        return f == ARK_ROOT_RETURN;
    }
    void roots_found(int* r) override { ERKStepGetRootInfo(mem, r); }
    void restart(double t, N_Vector y) override { ERKStepReInit(mem, rhs, t, y); }
    void count(long& steps, long& rejected) override
    {
        long s = 0, a = 0, e = 0;
        ERKStepGetNumSteps(mem, &s);
        ERKStepGetNumStepAttempts(mem, &a);
        ERKStepGetNumErrTestFails(mem, &e);
        steps += s;
        rejected += e;
    }
};

run_result run(const problem& p, const std::string& method)
{
    run_result res;
    SUNContext ctx;
    SUNContext_Create(nullptr, &ctx);
    context c{&p, p.delta() * p.delta(), p.alpha(), p.M()};
    N_Vector y = N_VNew_Serial(4, ctx);
    double* x = N_VGetArrayPointer(y);
    x[0] = 0.0;
    x[1] = 0.0;
    x[2] = 0.0;
    x[3] = 0.1;
    const auto wall0 = clock::now();
    {
        std::unique_ptr<solver> s;
        if (method == "cvode-adams") s = std::make_unique<cvode_adams>(ctx, c, y);
        else s = std::make_unique<arkode_erk>(ctx, c, y);
        double t = 0.0;
        while (!res.done(p) && t < p.t_end()) {
            if (!s->evolve(p.t_end(), y, &t)) break;
            int r[2] = {0, 0};
            s->roots_found(r);
            // A section root at the impact's own time belongs before it (as in the other baselines).
            if (r[1] != 0 && res.recording(p)) {
                res.points.push_back({t, {x[0], x[1], x[2], x[3]}});
                if (res.done(p)) break;
            }
            if (r[0] != 0) {
                x[0] = p.sigma;
                x[1] = -p.r * x[1];
                ++res.impacts;
                s->count(res.steps, res.rejected);
                s->restart(t, y);
            }
        }
        s->count(res.steps, res.rejected);
    }
    res.wall_s = seconds_since(wall0);
    res.rhs_calls = c.rhs_calls;
    N_VDestroy(y);
    SUNContext_Free(&ctx);
    return res;
}

}  // namespace

int main(int argc, char** argv)
{
    const auto a = parse_with_method(argc, argv, {"cvode-adams", "arkode-erk"});
    if (!a) return 2;
    const auto& [method, p] = *a;
    return report(p, method.c_str(), [&] { return run(p, method); });
}
