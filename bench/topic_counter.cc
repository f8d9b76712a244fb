// bench_topic_counter: a light subscriber for bench/node_throughput.py. It subscribes to the
// topics named on its command line with any type and counts their messages and bytes without
// deserialising them, so that the benchmark measures the node that sends them rather than the
// receiver.
//
//   bench_topic_counter TOPIC [TOPIC ...]
//
// Every 100 ms of wall time it prints one line to stdout:
//
//   counts <monotonic s> <messages of TOPIC 1> <bytes of TOPIC 1> <messages of TOPIC 2> ...
//
// with cumulative counts since it started and the time of CLOCK_MONOTONIC (Python's
// time.monotonic() on Linux), so the reader can difference two lines over its own window.
#include <ros/ros.h>

#include <cstdint>
#include <cstdio>
#include <ctime>
#include <string>
#include <vector>

namespace {

// A message of any type, of which only the serialised length is kept. The md5sum and type "*"
// are the wildcard that publishers accept (as topic_tools::ShapeShifter uses them).
struct RawMessage {
  std::uint32_t length = 0;
};

struct TopicCount {
  std::uint64_t messages = 0;
  std::uint64_t bytes = 0;
};

double monotonicSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

}  // namespace

namespace ros {
namespace message_traits {
template <>
struct MD5Sum<RawMessage> {
  static const char* value() { return "*"; }
  static const char* value(const RawMessage&) { return value(); }
};
template <>
struct DataType<RawMessage> {
  static const char* value() { return "*"; }
  static const char* value(const RawMessage&) { return value(); }
};
template <>
struct Definition<RawMessage> {
  static const char* value() { return ""; }
  static const char* value(const RawMessage&) { return value(); }
};
}  // namespace message_traits

namespace serialization {
template <>
struct Serializer<RawMessage> {
  // Reading only records the length: the bytes are never looked at.
  template <typename Stream>
  static void read(Stream& stream, RawMessage& m) {
    m.length = stream.getLength();
  }
};
}  // namespace serialization
}  // namespace ros

int main(int argc, char** argv) {
  ros::init(argc, argv, "bench_topic_counter", ros::init_options::AnonymousName);
  std::vector<std::string> topics(argv + 1, argv + argc);
  if (topics.empty()) {
    std::fprintf(stderr, "usage: bench_topic_counter TOPIC [TOPIC ...]\n");
    return 2;
  }
  ros::NodeHandle nh;
  std::vector<TopicCount> counts(topics.size());
  std::vector<ros::Subscriber> subscribers;
  for (std::size_t i = 0; i < topics.size(); ++i) {
    TopicCount* count = &counts[i];
    // A short queue: when the counter falls behind, roscpp drops the oldest (the counts say
    // what arrived, so a lower received rate than the published one shows it).
    subscribers.push_back(nh.subscribe<RawMessage>(
        topics[i], 10,
        [count](const boost::shared_ptr<const RawMessage>& m) {
          ++count->messages;
          count->bytes += m->length;
        },
        ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay()));
  }
  // One thread: the timer and the callbacks run in ros::spin, so the counts need no lock.
  ros::WallTimer report =
      nh.createWallTimer(ros::WallDuration(0.1), [&](const ros::WallTimerEvent&) {
        std::printf("counts %.6f", monotonicSeconds());
        for (const TopicCount& c : counts)
          std::printf(" %llu %llu", static_cast<unsigned long long>(c.messages),
                      static_cast<unsigned long long>(c.bytes));
        std::printf("\n");
        std::fflush(stdout);
      });
  ros::spin();
  return 0;
}
