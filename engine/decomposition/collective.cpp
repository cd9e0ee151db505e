// agree(): the outcome of a local step, made the same on every rank.
#include "collective.hpp"

#include "common/errors.hpp"

namespace semlb::engine {

void agree(const Mpi& mpi, const std::function<void()>& local) {
  std::string message;
  int code = 0;
  try {
    local();
  } catch (const AgreedError& e) {
    message = e.what();
    code = e.code;
  } catch (const InputError& e) {
    message = e.what();
    code = 2;
  } catch (const std::exception& e) {
    message = e.what();
    code = 1;
  }
  const auto codes = mpi.allgather({static_cast<double>(code)});
  int first = 0;
  while (first < mpi.size() && codes[first] == 0) ++first;
  if (first == mpi.size()) return;
  const std::string mine = message;
  mpi.broadcast(message, first);  // every rank now holds the first failing rank's message
  const auto same = mpi.allgather({code != 0 && mine == message ? 1.0 : 0.0});
  bool everyone = true;
  for (int r = 0; r < mpi.size(); ++r) everyone = everyone && same[r] > 0;
  throw AgreedError((everyone ? "" : "rank " + std::to_string(first) + ": ") + message, static_cast<int>(codes[first]));
}

}  // namespace semlb::engine
