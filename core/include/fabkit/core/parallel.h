#pragma once
// Independent pieces of work run at once on a few threads (the solver's independent groups,
// for one): each index runs exactly once, results go wherever the callee writes them (one
// slot per index, so the order the threads happen to take does not change any answer), and
// the first exception any piece throws is rethrown on the calling thread after all stop.

#include <functional>

namespace fabkit {

/// How many threads `threads` asks for: itself when positive, else one per core (at least 1).
int thread_count(int threads);

/// Starts the threads run_in_parallel hands work to (up to `threads`, counted as thread_count
/// does, the calling thread among them), if they are not running yet. They are kept for the
/// process's life; calling this early (before reading a design) lets them be running by the
/// time a solve needs them, as a new thread can take milliseconds to be first scheduled.
void start_helper_threads(int threads);

/// Calls `work(i)` for every i in [0, count) on up to `threads` threads, the calling thread
/// among them (the others are kept between calls: start_helper_threads); returns when all have
/// returned. An index is taken only after every lower one was, each by a thread that runs it
/// (so a piece may wait for a lower one). An exception stops the handing out of further
/// indices and is rethrown here (the first one thrown).
void run_in_parallel(int count, int threads, const std::function<void(int)>& work);

}  // namespace fabkit
