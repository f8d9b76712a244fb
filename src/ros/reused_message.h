// ReusedMessage: an output message the node keeps from tick to tick and overwrites (with the
// fill… conversions, conversions.h) instead of building it anew, so that a tick of 10 000
// bodies allocates no strings or arrays. It is published as a shared pointer: roscpp
// serialises it once for all its TCP subscribers and copies nothing.
#pragma once

#include <boost/make_shared.hpp>
#include <boost/shared_ptr.hpp>
#include <cstdint>

namespace cga_rigid_sim {
namespace node {

template <class M>
class ReusedMessage {
 public:
  /// The message to overwrite. roscpp keeps a published pointer only to hand it to a
  /// subscriber in this same process later (intraprocess); while it does, the message must stay
  /// as it was sent, so it is left to roscpp and a copy is overwritten instead.
  M& writable() {
    if (!msg_)
      msg_ = boost::make_shared<M>();
    else if (msg_.use_count() > 1)
      msg_ = boost::make_shared<M>(*msg_);
    return *msg_;
  }
  /// The message as last written (null before the first writable()).
  const boost::shared_ptr<M>& ptr() const { return msg_; }

  /// Whether the names must be written for topology version `version` (World::topologyVersion)
  /// — the first time, and after every change of the set of bodies; remembers `version`.
  bool namesChangedFor(std::uint64_t version) {
    const bool changed = version != names_version_;
    names_version_ = version;
    return changed;
  }

 private:
  boost::shared_ptr<M> msg_;
  std::uint64_t names_version_ = UINT64_MAX;
};

}  // namespace node
}  // namespace cga_rigid_sim
