#pragma once
/// What a deadline cut short, said so a person can act on it: a connect whose cycle-closure
/// search the deadline stopped is not shown impossible, and a solve stopped at its deadline
/// still has a best result. Front ends (CLI, server, Python) use these for their messages.

#include <string>

#include "fabkit/hacks/assembly.h"
#include "fabkit/hacks/solve.h"

namespace fabkit::hacks {

/// When a rejected connect's cycle-closure search was cut short by `verify.deadline` (fewer
/// starts than `verify.restarts`, the deadline passed), the rejection says nothing about the
/// design: its closure errors become one time-limit error ("stopped at the deadline after N
/// iterations ...") keeping the best configuration found. Returns whether it did.
bool mark_cut_by_deadline(ConnectReport& report, const VerifyOptions& verify);

/// "stopped at the deadline after N iterations of step 1 (starts, of M) ...; the best result
/// so far: the target is X mm and Y° from its goal" for a solve that ended at its deadline.
std::string stopped_at_deadline(const SolveResult& result, const SolveOptions& options);

}  // namespace fabkit::hacks
