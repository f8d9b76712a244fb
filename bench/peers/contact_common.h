// Shared driver of the contact runners (peer_contacts_<engine>, and our
// bench_contacts, which compiles it in without any peer engine): the
// sweep over contact cases x configs x step sizes, timing, error evaluation
// (bench/cases/contact_cases.h) and the CSV writer.
//
// Timing protocol (same spirit as peer_common.h, adapted to short runs):
//   * ns_per_step = median over `reps` (default 3) fresh simulations of the
//     wall time (steady_clock) of the complete run to T (T/h steps) without
//     any state read-back, divided by T/h; construction excluded. The
//     thread-CPU time of the same runs goes to cpu_contacts_<engine>.csv.
//   * the errors come from a separate complete run that reads the state
//     after every step (ContactMonitor).
//   * cases marked observe_end_only (pile1000) are run once: the timed run
//     is also the error run (the state is read only at the end).
//   * every run executes in a forked child, so an engine abort loses only
//     that run (reported as error inf, metric "crashed").
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "contact_cases.h"

namespace bench {
namespace contacts {

class ContactSim {
 public:
  virtual ~ContactSim() = default;
  virtual void step(long n) = 0;
  // State of the dynamic bodies, in the order of ContactCase::bodies.
  virtual void observe(std::vector<BodyObs>* out) = 0;
  // Engine events worth a note (e.g. MuJoCo warnings); no commas.
  virtual std::string events() { return ""; }
};

using ContactFactory = std::function<std::unique_ptr<ContactSim>(const ContactCase&, double h)>;

struct ContactConfig {
  std::string name;
  ContactFactory make;
  // Cases this config does not run (with the reason, printed to the log).
  std::vector<std::string> skip_cases;
  std::string skip_reason;
};

// bench/out/contacts_<engine>.csv
class ContactCsv {
 public:
  explicit ContactCsv(const std::string& path);
  ~ContactCsv();
  ContactCsv(const ContactCsv&) = delete;
  ContactCsv& operator=(const ContactCsv&) = delete;
  static const char* header() { return "engine,config,case,h,ns_per_step,error,error_metric,notes"; }
  void row(const std::string& engine, const std::string& config, const std::string& case_name, double h,
           double ns_per_step, double error, const std::string& metric, const std::string& notes);

 private:
  void* file_;
};

// default_pile_T > 0: this engine's default simulated time of pile1000 (a
// budget cut for slow engines, printed in the notes; --pile-T overrides).
int runContactSweep(const std::string& engine, const std::string& version, const std::vector<ContactConfig>& configs,
                    int argc, char** argv, double default_pile_T = 0);

}  // namespace contacts
}  // namespace bench
