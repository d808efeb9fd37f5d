// LiveConnection (adaptor/insitu/LiveConnection.h), through its own header, on
// real MPI ranks with ParaView Catalyst started (its proxy manager and global
// controller are what the link uses): the Catalyst Live address as a user
// writes it, accepted or refused with a message; and what a step's Live
// exchange costs when no viewer is there. Where nothing listens, the attempt is
// refused at once, with no warning, and made again at the next step; where
// something accepts the connection and never answers (a hung viewer, another
// service), the attempt ends after the stall limit with one warning naming the
// address, and the next step does not try again (a minute later it would).
#include "LiveConnection.h"

#include <gtest/gtest.h>
#include <mpi.h>

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

namespace canopy::testing
{
namespace
{

int rank()
{
  int value = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &value);
  return value;
}

TEST(LiveConnectionUrl, HostAndPortAsAUserWritesThem)
{
  struct Case
  {
    const char* url;
    const char* host;
    int port;
  };
  for (const Case& c : {Case{"viewer.example.org:11111", "viewer.example.org", 11111},
                        Case{"viewer.example.org", "viewer.example.org", 22222},
                        Case{"10.0.0.7:1", "10.0.0.7", 1}, Case{":5000", "localhost", 5000},
                        Case{"", "localhost", 22222}, Case{"localhost:65533", "localhost", 65533}})
  {
    LiveConnection::Settings settings;
    settings.pauseLimitSeconds = 12;
    settings.stallSeconds = 3;
    std::string error;
    EXPECT_TRUE(LiveConnection::parseUrl(c.url, settings, error)) << c.url;
    EXPECT_EQ(settings.host, c.host) << c.url;
    EXPECT_EQ(settings.port, c.port) << c.url;
    EXPECT_EQ(error, "") << c.url;
    // The other settings are not the address's.
    EXPECT_EQ(settings.pauseLimitSeconds, 12);
    EXPECT_EQ(settings.stallSeconds, 3);
  }
}

TEST(LiveConnectionUrl, PortsThatCannotBeUsedAreRefusedWithAMessage)
{
  // The viewer listens on the port and on the next ones (one per simulation
  // rank it reads from): 65533 is the last usable.
  for (const char* url :
       {"localhost:0", "localhost:65534", "localhost:65536", "localhost:", "localhost:12ab",
        "localhost:-5", "localhost:2.5", "localhost:99999999999999999999"})
  {
    LiveConnection::Settings settings;
    std::string error;
    EXPECT_FALSE(LiveConnection::parseUrl(url, settings, error)) << url;
    EXPECT_EQ(error, std::string("Catalyst Live address '") + url +
                         "': the port must be a number from 1 to 65533 (the viewer also "
                         "listens on the next ports, one per simulation rank it reads from)");
  }
}

/// A TCP socket listening on a free port of 127.0.0.1 that accepts connections
/// in the kernel and never reads or answers (on rank 0; the port is broadcast).
class SilentListener
{
public:
  /// On `port`, or on a free port the kernel picks.
  explicit SilentListener(int port = 0)
  {
    if (rank() == 0)
    {
      Socket = socket(AF_INET, SOCK_STREAM, 0);
      const int yes = 1;
      setsockopt(Socket, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
      sockaddr_in address{};
      address.sin_family = AF_INET;
      address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
      address.sin_port = htons(static_cast<std::uint16_t>(port));
      socklen_t length = sizeof address;
      if (bind(Socket, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0 &&
          listen(Socket, 16) == 0 &&
          getsockname(Socket, reinterpret_cast<sockaddr*>(&address), &length) == 0)
      {
        Port = ntohs(address.sin_port);
        fcntl(Socket, F_SETFL, O_NONBLOCK);
      }
    }
    MPI_Bcast(&Port, 1, MPI_INT, 0, MPI_COMM_WORLD);
  }
  ~SilentListener() { stop(); }
  SilentListener(const SilentListener&) = delete;
  SilentListener& operator=(const SilentListener&) = delete;

  int port() const { return Port; }

  /// Connections made to it since the last call (rank 0; 0 elsewhere). They
  /// are closed at once, unanswered.
  int connections()
  {
    int count = 0;
    for (int accepted = 0; Socket >= 0 && (accepted = accept(Socket, nullptr, nullptr)) >= 0;)
    {
      close(accepted);
      ++count;
    }
    return count;
  }

  /// Nothing listens on the port any more: connecting is refused.
  void stop()
  {
    if (Socket >= 0)
    {
      close(Socket);
      Socket = -1;
    }
  }

private:
  int Socket = -1;
  int Port = -1;
};

using Clock = std::chrono::steady_clock;

/// One Live exchange of step `step`, timed.
std::vector<std::string> timedUpdate(LiveConnection& live, std::int64_t step, double& seconds)
{
  const auto start = Clock::now();
  std::vector<std::string> warnings = live.update(0.1 * static_cast<double>(step), step);
  seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return warnings;
}

LiveConnection::Settings localSettings(int port)
{
  LiveConnection::Settings settings;
  settings.host = "localhost";
  settings.port = port;
  settings.stallSeconds = 2.0;
  return settings;
}

TEST(LiveConnection, WhereNothingListensEachStepTriesOnceAtOnceWithoutWarning)
{
  SilentListener listener;
  ASSERT_GT(listener.port(), 0);
  const int port = listener.port();
  listener.stop(); // a port nothing listens on: refused
  LiveConnection live(localSettings(port));
  for (std::int64_t step = 0; step < 3; ++step)
  {
    double seconds = 0;
    const auto warnings = timedUpdate(live, step, seconds);
    EXPECT_TRUE(warnings.empty()) << warnings.front();
    EXPECT_LT(seconds, 1.0) << "step " << step << ": a refused connection costs no wait";
    EXPECT_FALSE(live.connected());
  }
}

TEST(LiveConnection, AListenerThatNeverAnswersCostsOneBoundedWait)
{
  SilentListener listener;
  ASSERT_GT(listener.port(), 0);
  LiveConnection live(localSettings(listener.port()));
  double seconds = 0;
  auto warnings = timedUpdate(live, 1, seconds);
  EXPECT_GE(seconds, 2.0) << "it waited for the stall limit";
  EXPECT_LT(seconds, 6.0) << "and not much longer";
  EXPECT_FALSE(live.connected());
  if (rank() == 0)
  {
    EXPECT_EQ(listener.connections(), 1);
    EXPECT_EQ(warnings,
              std::vector<std::string>{
                  "something at localhost:" + std::to_string(listener.port()) +
                  " accepted the connection but did not answer for 2 s (not a "
                  "ParaView 5.11 viewer, or a stalled one); the next attempt is in 60 s"});
  }
  // The next steps do not try again (for a minute): no wait, no connection.
  for (std::int64_t step = 2; step < 4; ++step)
  {
    warnings = timedUpdate(live, step, seconds);
    EXPECT_LT(seconds, 1.0) << "step " << step;
    EXPECT_TRUE(warnings.empty()) << "step " << step;
  }
  EXPECT_EQ(listener.connections(), 0);
}

TEST(LiveConnection, AfterARefusalTheNextStepTriesAgain)
{
  // Refused at step 1; at step 2 something listens on that port: it is tried.
  int port = 0;
  {
    SilentListener probe;
    port = probe.port();
  }
  ASSERT_GT(port, 0);
  LiveConnection live(localSettings(port));
  double seconds = 0;
  EXPECT_TRUE(timedUpdate(live, 1, seconds).empty());
  EXPECT_LT(seconds, 1.0);
  SilentListener listener(port);
  ASSERT_EQ(listener.port(), port);
  timedUpdate(live, 2, seconds);
  EXPECT_GE(seconds, 2.0) << "the silent listener held the attempt for the stall limit";
  if (rank() == 0)
  {
    EXPECT_EQ(listener.connections(), 1);
  }
}

} // namespace
} // namespace canopy::testing
