// Errors in a decomposed run reach every rank: a verdict agreed collectively, or one rank's error that ends
// the job (docs/engine.md "Failures").
#pragma once
#include <functional>
#include <stdexcept>
#include <string>

#include "mpi.hpp"

namespace semlb::engine {

// An error that every rank of a decomposed run throws at the same point with the same message (a verdict
// reached collectively), so that the job can end normally with exit code `code` (1: run-time failure,
// 2: bad input). `failed_step` >= 0 marks a numerical failure at that step: failure.h5 is due. Any other
// exception in a decomposed run is one rank's alone; `semlb sim` then ends the job with MPI_Abort.
struct AgreedError : std::runtime_error {
  AgreedError(const std::string& message, int code, long failed_step = -1)
      : std::runtime_error(message), code(code), failed_step(failed_step) {}
  int code;
  long failed_step;
};

// Runs `local` (which must not call collectives) on every rank, then agrees on the outcome: if it threw
// on any rank, every rank throws AgreedError with the message of the lowest failing rank, prefixed
// "rank R: " unless every rank failed with that same message, and code 2 for an InputError, else 1.
void agree(const Mpi& mpi, const std::function<void()>& local);

}  // namespace semlb::engine
