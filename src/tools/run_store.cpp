#include "run_store.hpp"

#include <dlfcn.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>

#include "coil_winding_sim/core/base/checksum.hpp"
#include "coil_winding_sim/core/run/output.hpp"

namespace cws_tools {

uint64_t fnv1a(const std::string& bytes) { return cws::fnv1a(bytes.data(), bytes.size()); }

uint64_t coreBuildHash() {
  static const uint64_t hash = [] {
    Dl_info info{};
    const void* symbol = reinterpret_cast<const void*>(&cws::Simulation::fromState);
    if (dladdr(symbol, &info) == 0 || !info.dli_fname) return uint64_t{0};
    std::ifstream f(info.dli_fname, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    return bytes.empty() ? uint64_t{0} : fnv1a(bytes);
  }();
  return hash;
}

namespace {

constexpr char kMagic[] = "cws-stability-checkpoint/4";

// Little binary writer and reader: numbers as their bytes, strings and
// vectors with their length first.
struct Writer {
  std::string out;
  template <class T>
  void pod(const T& v) {
    out.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  void str(const std::string& s) {
    pod<uint64_t>(s.size());
    out += s;
  }
  void vec(const std::vector<double>& v) {
    pod<uint64_t>(v.size());
    out.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(double));
  }
};

struct Reader {
  const std::string& in;
  std::size_t at = 0;
  bool ok = true;
  template <class T>
  void pod(T& v) {
    if (!ok || in.size() - at < sizeof v) {
      ok = false;
      return;
    }
    std::memcpy(&v, in.data() + at, sizeof v);
    at += sizeof v;
  }
  // A length no larger than what is left: a corrupt one fails here.
  bool length(uint64_t& n, std::size_t unit) {
    pod(n);
    ok = ok && n <= (in.size() - at) / unit;
    return ok;
  }
  void str(std::string& s) {
    uint64_t n = 0;
    if (!length(n, 1)) return;
    s.assign(in, at, n);
    at += n;
  }
  void vec(std::vector<double>& v) {
    uint64_t n = 0;
    if (!length(n, sizeof(double))) return;
    v.resize(n);
    std::memcpy(v.data(), in.data() + at, n * sizeof(double));
    at += n * sizeof(double);
  }
};

// Every field of a checkpoint, in one order for writing and reading.
template <class Io>
void fields(Io& io, Checkpoint& c) {
  cws::SimulationState& s = c.state;
  cws::ModelState& m = s.model;
  io.pod(c.identity);
  io.pod(c.wall_s);
  uint64_t next_event = c.next_event;
  io.pod(next_event);
  c.next_event = next_event;
  io.str(s.scene_yaml);
  io.pod(s.time_s);
  io.pod(m.points);
  io.vec(m.y);
  io.vec(m.history);
  for (double& v : m.core) io.pod(v);
  // The setpoints held, three numbers each: kind, value, value2 (a kind
  // the table lacks is dropped; the file's checksum guards the rest).
  std::vector<double> held;
  for (const cws::Setpoint& sp : s.held) {
    held.insert(held.end(), {static_cast<double>(sp.kind), sp.value, sp.value2});
  }
  io.vec(held);
  s.held.clear();
  for (std::size_t i = 0; i + 3 <= held.size(); i += 3) {
    if (!(held[i] >= 0.0 && held[i] < static_cast<double>(cws::setpointTable().size()))) continue;
    cws::Setpoint sp;
    sp.kind = static_cast<cws::Setpoint::Kind>(static_cast<int>(held[i]));
    sp.value = held[i + 1];
    sp.value2 = held[i + 2];
    s.held.push_back(sp);
  }
  io.pod(m.points_added);
  io.pod(m.committed_time_s);
  io.pod(m.port_distance0_m);
  io.pod(m.carried);
  io.vec(m.carried_pose);
  io.vec(m.port_command);
  io.pod(m.retired);
  io.vec(m.retired_points);
  for (double& v : m.retired_energy) io.pod(v);
  for (double& v : m.clamp_core) io.pod(v);
  io.pod(s.next_step_s);
  io.pod(s.last_step_s);
  io.pod(s.counts.accepted);
  io.pod(s.counts.rejected);
  io.pod(s.counts.derivative_evaluations);
  io.pod(s.max_residual);
  io.pod(s.max_axial_force_N);
  io.pod(s.max_penetration_m);
  io.pod(s.wall_time_s);
}

}  // namespace

void writeCheckpoint(const std::string& path, const Checkpoint& c) {
  Writer w;
  w.out = kMagic;
  Checkpoint copy = c;
  fields(w, copy);
  w.pod(fnv1a(w.out));  // the whole file's checksum last
  cws::writeFileAtomically(path, w.out);
}

bool readCheckpoint(const std::string& path, Checkpoint& c) {
  std::ifstream f(path, std::ios::binary);
  if (!f) return false;
  const std::string in((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  const std::size_t magic = std::strlen(kMagic);
  if (in.size() < magic + sizeof(uint64_t) || in.compare(0, magic, kMagic) != 0) return false;
  uint64_t sum = 0;
  std::memcpy(&sum, in.data() + in.size() - sizeof sum, sizeof sum);
  const std::string body = in.substr(0, in.size() - sizeof sum);
  if (fnv1a(body) != sum) return false;
  Reader r{body, magic};
  Checkpoint read;
  fields(r, read);
  if (!r.ok || r.at != body.size()) return false;
  c = std::move(read);
  return true;
}

}  // namespace cws_tools
