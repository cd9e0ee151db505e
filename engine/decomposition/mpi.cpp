// MPI wrapper: initialisation, checked collectives on byte buffers.
#include "mpi.hpp"

#include <cstdlib>
#include <numeric>
#include <stdexcept>

namespace semlb::engine {
namespace {
void check(int rc, const char* what) {
  if (rc != MPI_SUCCESS) {
    char text[MPI_MAX_ERROR_STRING];
    int n = 0;
    MPI_Error_string(rc, text, &n);
    throw std::runtime_error(std::string("MPI: ") + what + " failed: " + std::string(text, n));
  }
}
}  // namespace

bool Mpi::launched() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "SLURM_PROCID"})
    if (std::getenv(v)) return true;
  return false;
}

Mpi::Mpi() {
  int ready = 0;
  MPI_Initialized(&ready);
  if (!ready) {
    check(MPI_Init(nullptr, nullptr), "MPI_Init");
    owns_ = true;
  }
  MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
  check(MPI_Comm_rank(MPI_COMM_WORLD, &rank_), "MPI_Comm_rank");
  check(MPI_Comm_size(MPI_COMM_WORLD, &size_), "MPI_Comm_size");
}

Mpi::~Mpi() {
  if (owns_) MPI_Finalize();
}

int Mpi::local_rank() const {
  MPI_Comm local;
  check(MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &local), "split");
  int r = 0;
  MPI_Comm_rank(local, &r);
  MPI_Comm_free(&local);
  return r;
}

std::vector<double> Mpi::allgather(const std::vector<double>& mine) const {
  const int k = static_cast<int>(mine.size());
  std::vector<double> out(static_cast<size_t>(k) * size_);
  check(MPI_Allgather(mine.data(), k, MPI_DOUBLE, out.data(), k, MPI_DOUBLE, MPI_COMM_WORLD), "MPI_Allgather");
  return out;
}

void Mpi::allreduce_sum(std::vector<double>& v) const {
  check(MPI_Allreduce(MPI_IN_PLACE, v.data(), static_cast<int>(v.size()), MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD),
        "MPI_Allreduce");
}

void Mpi::allreduce_sum(std::vector<int>& v) const {
  check(MPI_Allreduce(MPI_IN_PLACE, v.data(), static_cast<int>(v.size()), MPI_INT, MPI_SUM, MPI_COMM_WORLD),
        "MPI_Allreduce");
}

long Mpi::allreduce_max(long value) const {
  check(MPI_Allreduce(MPI_IN_PLACE, &value, 1, MPI_LONG, MPI_MAX, MPI_COMM_WORLD), "MPI_Allreduce");
  return value;
}

void Mpi::broadcast(std::vector<int>& v, int root) const {
  int n = static_cast<int>(v.size());
  check(MPI_Bcast(&n, 1, MPI_INT, root, MPI_COMM_WORLD), "MPI_Bcast");
  v.resize(n);
  check(MPI_Bcast(v.data(), n, MPI_INT, root, MPI_COMM_WORLD), "MPI_Bcast");
}

void Mpi::broadcast(std::string& text, int root) const {
  int n = static_cast<int>(text.size());
  check(MPI_Bcast(&n, 1, MPI_INT, root, MPI_COMM_WORLD), "MPI_Bcast");
  text.resize(n);
  check(MPI_Bcast(text.data(), n, MPI_CHAR, root, MPI_COMM_WORLD), "MPI_Bcast");
}

std::vector<char> Mpi::sendrecv(const std::vector<char>& send, int to, int from) const {
  long n_send = static_cast<long>(send.size()), n_recv = 0;
  check(MPI_Sendrecv(&n_send, 1, MPI_LONG, to, 1, &n_recv, 1, MPI_LONG, from, 1, MPI_COMM_WORLD, MPI_STATUS_IGNORE),
        "MPI_Sendrecv");
  std::vector<char> recv(from == MPI_PROC_NULL ? 0 : n_recv);
  check(MPI_Sendrecv(send.data(), static_cast<int>(n_send), MPI_BYTE, to, 2, recv.data(), static_cast<int>(recv.size()),
                     MPI_BYTE, from, 2, MPI_COMM_WORLD, MPI_STATUS_IGNORE),
        "MPI_Sendrecv");
  return recv;
}

void Mpi::start_sendrecv(const std::vector<char>& send, int to, int from, std::vector<char>& recv, int tag,
                         Requests& pending) const {
  long n_send = static_cast<long>(send.size()), n_recv = 0;
  check(MPI_Sendrecv(&n_send, 1, MPI_LONG, to, tag, &n_recv, 1, MPI_LONG, from, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE),
        "MPI_Sendrecv");
  recv.resize(from == MPI_PROC_NULL ? 0 : n_recv);
  pending.receive(recv, from, tag + 1);
  pending.send(send, to, tag + 1);
}

Requests::~Requests() {
  for (MPI_Request& r : requests_) {
    if (r == MPI_REQUEST_NULL) continue;
    MPI_Cancel(&r);
    MPI_Request_free(&r);
  }
}

void Requests::send(const std::vector<char>& bytes, int to, int tag) {
  if (to == MPI_PROC_NULL) return;
  requests_.emplace_back(MPI_REQUEST_NULL);
  check(MPI_Isend(bytes.data(), static_cast<int>(bytes.size()), MPI_BYTE, to, tag, MPI_COMM_WORLD, &requests_.back()),
        "MPI_Isend");
}

void Requests::receive(std::vector<char>& bytes, int from, int tag) {
  if (from == MPI_PROC_NULL) return;
  requests_.emplace_back(MPI_REQUEST_NULL);
  check(MPI_Irecv(bytes.data(), static_cast<int>(bytes.size()), MPI_BYTE, from, tag, MPI_COMM_WORLD, &requests_.back()),
        "MPI_Irecv");
}

void Requests::wait() {
  const int rc = MPI_Waitall(static_cast<int>(requests_.size()), requests_.data(), MPI_STATUSES_IGNORE);
  if (rc == MPI_SUCCESS) requests_.clear();  // completed requests are MPI_REQUEST_NULL; on error the rest are freed
  check(rc, "MPI_Waitall");
}

void Requests::progress() {
  if (requests_.empty()) return;
  int done = 0;
  const int rc = MPI_Testall(static_cast<int>(requests_.size()), requests_.data(), &done, MPI_STATUSES_IGNORE);
  if (rc == MPI_SUCCESS && done) requests_.clear();
  check(rc, "MPI_Testall");
}

std::vector<std::vector<char>> Mpi::alltoall(const std::vector<std::vector<char>>& parts) const {
  std::vector<int> send_n(size_), recv_n(size_), send_off(size_), recv_off(size_);
  for (int r = 0; r < size_; ++r) send_n[r] = static_cast<int>(parts[r].size());
  check(MPI_Alltoall(send_n.data(), 1, MPI_INT, recv_n.data(), 1, MPI_INT, MPI_COMM_WORLD), "MPI_Alltoall");
  std::exclusive_scan(send_n.begin(), send_n.end(), send_off.begin(), 0);
  std::exclusive_scan(recv_n.begin(), recv_n.end(), recv_off.begin(), 0);
  std::vector<char> send, recv(recv_off.back() + recv_n.back());
  for (const auto& p : parts) send.insert(send.end(), p.begin(), p.end());
  check(MPI_Alltoallv(send.data(), send_n.data(), send_off.data(), MPI_BYTE, recv.data(), recv_n.data(),
                      recv_off.data(), MPI_BYTE, MPI_COMM_WORLD),
        "MPI_Alltoallv");
  std::vector<std::vector<char>> out(size_);
  for (int r = 0; r < size_; ++r) out[r].assign(recv.begin() + recv_off[r], recv.begin() + recv_off[r] + recv_n[r]);
  return out;
}

std::vector<std::vector<char>> Mpi::gather(const std::vector<char>& part, int root) const {
  std::vector<std::vector<char>> parts(size_);
  parts[root] = part;
  auto got = alltoall(parts);  // only the root receives anything
  return got;
}

void Mpi::barrier() const { check(MPI_Barrier(MPI_COMM_WORLD), "MPI_Barrier"); }

void Mpi::abort(int code) const {
  MPI_Abort(MPI_COMM_WORLD, code);
  std::abort();
}

}  // namespace semlb::engine
