// What the peer sweep drivers (peer_common.cc: free bodies; contact_common.cc: contacts;
// articulated_common.cc: trees)
// share: list options, filters, the thread CPU clock, and running one measurement in a forked
// child so that an engine that aborts on a diverged state loses only that run.
#pragma once

#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <exception>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

namespace bench {
namespace sweep {

// A free-text CSV field: commas, newlines and tabs replaced so the row keeps its columns.
inline std::string csvSafe(std::string s) {
  std::replace(s.begin(), s.end(), ',', ';');
  std::replace(s.begin(), s.end(), '\n', ' ');
  std::replace(s.begin(), s.end(), '\t', ' ');
  return s;
}

// "a,b,c" → {a, b, c} (empty items dropped).
inline std::vector<std::string> splitList(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string tok;
  while (std::getline(ss, tok, ','))
    if (!tok.empty()) out.push_back(tok);
  return out;
}

// An empty filter selects everything.
inline bool selected(const std::vector<std::string>& filter, const std::string& s) {
  return filter.empty() || std::find(filter.begin(), filter.end(), s) != filter.end();
}

inline double threadCpuSeconds() {
  timespec ts;
  ::clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

// Runs fn() (returning a text) in a forked child and hands the text back through a pipe.
// false if the child crashed, aborted or threw.
template <class Fn>
bool runIsolated(Fn fn, std::string* out) {
  int fd[2];
  if (::pipe(fd) != 0) return false;
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fd[0]);
    ::close(fd[1]);
    return false;
  }
  if (pid == 0) {
    ::close(fd[0]);
    int rc = 1;
    try {
      const std::string r = fn();
      size_t done = 0;
      while (done < r.size()) {
        const ssize_t n = ::write(fd[1], r.data() + done, r.size() - done);
        if (n <= 0) break;
        done += size_t(n);
      }
      if (done == r.size()) rc = 0;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "  exception: %s\n", e.what());
    }
    std::fflush(nullptr);
    ::_exit(rc);
  }
  ::close(fd[1]);
  std::string r;
  char buf[4096];
  for (;;) {
    const ssize_t n = ::read(fd[0], buf, sizeof buf);
    if (n <= 0) break;
    r.append(buf, size_t(n));
  }
  ::close(fd[0]);
  int status = 0;
  ::waitpid(pid, &status, 0);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) return false;
  *out = r;
  return true;
}

// The same for a result of plain data, sent as its bytes.
template <class T, class Fn>
bool runIsolatedValue(Fn fn, T* out) {
  static_assert(std::is_trivially_copyable<T>::value, "sent as bytes");
  std::string bytes;
  const bool ok = runIsolated(
      [&] {
        const T r = fn();
        return std::string(reinterpret_cast<const char*>(&r), sizeof r);
      },
      &bytes);
  if (!ok || bytes.size() != sizeof(T)) return false;
  std::memcpy(out, bytes.data(), sizeof(T));
  return true;
}

}  // namespace sweep
}  // namespace bench
