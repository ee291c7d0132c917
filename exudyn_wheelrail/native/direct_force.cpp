// The wheel-rail connector's force call as a compiled function Exudyn calls without Python.
//
// Exudyn takes a force user function as a std::function through pybind11.  When the object it is given is a
// pybind11 function wrapping a plain function pointer of exactly the expected type, pybind11 hands Exudyn that
// pointer: every call is then a C++ call (no Python objects, no interpreter).  This module offers SLOTS such
// functions (force_0, force_1, ...), each bound to a slot that holds the address of the package's compiled force
// evaluation (numba's native entry of multibody/direct_call.py's forces_step for the connector's argument types),
// the connector's data and its force vector.  The functions are registered with a call guard that counts the calls
// that do come through Python (pybind11's dispatcher): zero of them proves the direct path ran.
//
// The type Exudyn expects, std::vector<double>(const MainSystem&, double, int, std::vector<double>,
// std::vector<double>) (ObjectGenericODE2's forceUserFunction), is matched by name: MainSystem is declared here
// as an empty class of the same name; it is only passed by reference and never used.
//
// numba's native calling convention for forces_step(q, q_t, t, call) -> int64, which direct_call.py checks against
// numba's own description before it binds a slot: status (0: no exception) = f(int64* result, exception info**,
// then per float64 C-contiguous vector its fields meminfo, parent, nitems, itemsize, data, shape[0], strides[0],
// then t, then the CallData's meminfo).
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <cstdint>
#include <utility>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

class MainSystem {};

namespace {

using ForcesStep = std::int32_t (*)(std::int64_t*, void**,
                                    void*, void*, std::int64_t, std::int64_t, const double*, std::int64_t, std::int64_t,
                                    void*, void*, std::int64_t, std::int64_t, const double*, std::int64_t, std::int64_t,
                                    double, void*);

constexpr int SLOTS = 256;

struct Slot {
    ForcesStep call = nullptr;
    void* context = nullptr;         // the CallData's meminfo
    const double* f = nullptr;       // its force vector (n)
    std::int64_t n = 0;
    std::int64_t calls = 0;          // every call of the slot's function
    std::int64_t dispatched = 0;     // the calls that came through Python (pybind11's dispatcher)
    std::int64_t bad = -1;           // the latest bad state's code (-1: none) and its time
    double bad_t = 0.0;
    PyObject* binder = nullptr;      // binder(): binds `call` (through Python, once, before the first use);
                                     // binder.forces(t, q, q_t): the forces through Python where it could not
    bool used = false;
};

Slot slots[SLOTS];
thread_local bool in_dispatch = false;  // set by every slot function's call guard while pybind11's dispatcher (a call
                                     // from Python) runs it

std::vector<double> evaluate(int k, double t, const std::vector<double>& q, const std::vector<double>& q_t) {
    Slot& s = slots[k];
    if (in_dispatch) ++s.dispatched;
    if (s.call == nullptr) {
        if (s.binder == nullptr)
            throw std::runtime_error("wheel-rail contact: the compiled force call of slot " + std::to_string(k) +
                                     " was released (its connector no longer exists)");
        pybind11::gil_scoped_acquire gil;
        auto binder = pybind11::reinterpret_borrow<pybind11::object>(s.binder);
        if (!binder().cast<bool>()) {        // not bound: the connector's Python path, through Python
            ++s.calls;
            if (!in_dispatch) ++s.dispatched;
            return binder.attr("forces")(t, q, q_t).cast<std::vector<double>>();
        }
    }
    if (static_cast<std::int64_t>(q.size()) != s.n || static_cast<std::int64_t>(q_t.size()) != s.n)
        throw std::runtime_error("wheel-rail contact: the compiled force call got " + std::to_string(q.size()) +
                                 " coordinates, expected " + std::to_string(s.n));
    ++s.calls;
    std::int64_t bad = -1;
    void* exception = nullptr;
    const std::int64_t b = static_cast<std::int64_t>(sizeof(double));
    const std::int32_t status = s.call(&bad, &exception, nullptr, nullptr, s.n, b, q.data(), s.n, b,
                                       nullptr, nullptr, s.n, b, q_t.data(), s.n, b, t, s.context);
    if (status != 0)
        throw std::runtime_error("wheel-rail contact: the compiled force evaluation raised an exception (status " +
                                 std::to_string(status) + "); run with EXUDYN_WHEELRAIL_CALL_PATH=python to see it");
    if (bad >= 0) {
        s.bad = bad;                 // the latest: the one this exception reports
        s.bad_t = t;
        char text[256];
        std::snprintf(text, sizeof text, "wheel-rail contact at t = %.6g s: wheelset %lld has non-finite "
                      "coordinates (or the modal coordinates, if it is the last) - the simulation diverged "
                      "[compiled call slot %d]", t, static_cast<long long>(bad), k);
        throw std::runtime_error(text);
    }
    return std::vector<double>(s.f, s.f + s.n);
}

template <int K>
std::vector<double> force(const MainSystem&, double t, int, std::vector<double> q, std::vector<double> q_t) {
    return evaluate(K, t, q, q_t);
}

Slot& slot_at(int k) {
    if (k < 0 || k >= SLOTS) throw std::out_of_range("slot " + std::to_string(k) + " out of range");
    return slots[k];
}

struct DispatchGuard {
    DispatchGuard() { in_dispatch = true; }
    ~DispatchGuard() { in_dispatch = false; }
};

using SlotFunction = std::vector<double> (*)(const MainSystem&, double, int, std::vector<double>, std::vector<double>);

template <int... K>
constexpr std::array<SlotFunction, sizeof...(K)> slot_functions(std::integer_sequence<int, K...>) {
    return {&force<K>...};
}

}  // namespace

PYBIND11_MODULE(direct_force, m) {
    m.doc() = "The wheel-rail connector's force call as compiled functions Exudyn calls without Python.";
    m.attr("SLOTS") = SLOTS;
    static constexpr auto functions = slot_functions(std::make_integer_sequence<int, SLOTS>{});
    for (int k = 0; k < SLOTS; ++k)
        m.def(("force_" + std::to_string(k)).c_str(), functions[k], pybind11::call_guard<DispatchGuard>());
    m.def("acquire", [](std::int64_t n, pybind11::object binder) {
        for (int k = 0; k < SLOTS; ++k) {
            if (!slots[k].used) {
                slots[k] = Slot();
                slots[k].n = n;
                slots[k].binder = binder.release().ptr();
                slots[k].used = true;
                return k;
            }
        }
        return -1;
    }, "A free slot for a contact call of n coordinates, or -1 when every slot is taken; `binder()` is called at "
       "the slot function's first call, before it has a contact call, and must bind one (bind).");
    m.def("bind", [](int k, std::uintptr_t call, std::uintptr_t context, std::uintptr_t f) {
        Slot& s = slot_at(k);
        s.call = reinterpret_cast<ForcesStep>(call);
        s.context = reinterpret_cast<void*>(context);
        s.f = reinterpret_cast<const double*>(f);
    }, "Bind slot k to the force evaluation at address `call` with the CallData's meminfo `context` and its force "
       "vector's data `f`.");
    m.def("unbind", [](int k) { slot_at(k).call = nullptr; },
          "Unbind slot k: its function asks its binder again (which then answers with the Python path).");
    m.def("release", [](int k) {
        Slot& s = slot_at(k);
        Py_XDECREF(s.binder);
        s = Slot();
    }, "Free slot k (its function then raises when called).");
    m.def("counts", [](int k) {
        const Slot& s = slot_at(k);
        return pybind11::make_tuple(s.calls, s.dispatched);
    }, "(calls, of which through Python) of slot k.");
    m.def("bad_state", [](int k) {
        Slot& s = slot_at(k);
        auto r = pybind11::make_tuple(s.bad, s.bad_t);
        s.bad = -1;
        return r;
    }, "(code, t) of the latest bad state slot k met since the last question (code -1: none); clears it.");
}
