#include "LiveConnection.h"

#include "VtkMessageCapture.h"

#include <canopy/io/vtkCanopyHyperTreeGridPacker.h>

#include <vtkAlgorithm.h>
#include <vtkAlgorithmOutput.h>
#include <vtkClientSocket.h>
#include <vtkCommunicator.h>
#include <vtkExtractsDeliveryHelper.h>
#include <vtkHyperTreeGrid.h>
#include <vtkLiveInsituLink.h>
#include <vtkMultiProcessController.h>
#include <vtkMultiProcessStream.h>
#include <vtkPolyData.h>
#include <vtkSMProxyManager.h>
#include <vtkSMSessionProxyManager.h>
#include <vtkSocket.h>
#include <vtkSocketCommunicator.h>
#include <vtkSocketController.h>
#include <vtkTrivialProducer.h>
#include <vtk_loguru.h>

#include <cctype>
#include <csignal>
#include <cstdio>
#include <ctime>
#include <netinet/in.h>
#include <sys/socket.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <thread>

namespace canopy
{
namespace
{

// ParaView keeps the link's sockets and the extracts a viewer asked for in
// protected members; a pointer to a member named through a derived class reads
// them without changing ParaView.
struct LinkAccess : vtkLiveInsituLink
{
  static vtkMultiProcessController* control(vtkLiveInsituLink* link)
  {
    return (link->*(&LinkAccess::Proc0NodesController)).GetPointer();
  }
  static vtkExtractsDeliveryHelper* delivery(vtkLiveInsituLink* link)
  {
    return (link->*(&LinkAccess::ExtractsDeliveryHelper)).GetPointer();
  }
};

struct DeliveryAccess : vtkExtractsDeliveryHelper
{
  static auto& producers(vtkExtractsDeliveryHelper* helper)
  {
    return helper->*(&DeliveryAccess::ExtractProducers);
  }
  static vtkMultiProcessController* data(vtkExtractsDeliveryHelper* helper)
  {
    return (helper->*(&DeliveryAccess::Simulation2VisualizationController)).GetPointer();
  }
};

int descriptorOf(vtkMultiProcessController* controller)
{
  auto* socket =
      controller ? vtkSocketCommunicator::SafeDownCast(controller->GetCommunicator()) : nullptr;
  return socket && socket->GetSocket() ? socket->GetSocket()->GetSocketDescriptor() : -1;
}

vtkMultiProcessController* ranks()
{
  return vtkMultiProcessController::GetGlobalController();
}

int rankOf(vtkMultiProcessController* controller)
{
  return controller ? controller->GetLocalProcessId() : 0;
}

/// SIGPIPE blocked while it lives: VTK 9.2's sockets send without
/// MSG_NOSIGNAL, so a viewer that disconnects mid-transfer would otherwise
/// terminate the simulation. A SIGPIPE raised meanwhile is consumed.
class SigpipeBlocked
{
public:
  SigpipeBlocked()
  {
    sigemptyset(&this->Pipe);
    sigaddset(&this->Pipe, SIGPIPE);
    sigset_t pending;
    sigpending(&pending);
    this->WasPending = sigismember(&pending, SIGPIPE) == 1;
    pthread_sigmask(SIG_BLOCK, &this->Pipe, &this->Previous);
  }
  ~SigpipeBlocked()
  {
    sigset_t pending;
    sigpending(&pending);
    if (!this->WasPending && sigismember(&pending, SIGPIPE) == 1)
    {
      const timespec now{0, 0};
      sigtimedwait(&this->Pipe, nullptr, &now);
    }
    pthread_sigmask(SIG_SETMASK, &this->Previous, nullptr);
  }
  SigpipeBlocked(const SigpipeBlocked&) = delete;
  SigpipeBlocked& operator=(const SigpipeBlocked&) = delete;

private:
  sigset_t Pipe;
  sigset_t Previous;
  bool WasPending = false;
};

/// Nothing printed to stderr while it lives (VtkMessageCapture still collects):
/// ParaView's link and VTK's sockets log a viewer's disconnection as errors, and
/// a viewer must cost the simulation one warning at most, Canopy's own.
class QuietStderr
{
public:
  QuietStderr() : Saved(loguru::g_stderr_verbosity)
  {
    loguru::g_stderr_verbosity = loguru::Verbosity_OFF;
  }
  ~QuietStderr() { loguru::g_stderr_verbosity = this->Saved; }
  QuietStderr(const QuietStderr&) = delete;
  QuietStderr& operator=(const QuietStderr&) = delete;

private:
  loguru::Verbosity Saved;
};

/// Shuts down this process's TCP sockets connected to one of `ports` (the
/// viewer's ports this rank talks to). Found through /proc/self/fd, because
/// ParaView's link opens them inside calls that can block (connecting, its
/// handshake) before Canopy could know them.
void shutDownSocketsTo(const std::vector<int>& ports)
{
  std::error_code error;
  std::filesystem::directory_iterator entry("/proc/self/fd", error);
  // Never throws: the guard's thread must not terminate the simulation.
  for (; !error && entry != std::filesystem::directory_iterator(); entry.increment(error))
  {
    const std::string name = entry->path().filename().string();
    char* end = nullptr;
    const long descriptor = std::strtol(name.c_str(), &end, 10);
    if (name.empty() || *end != '\0')
    {
      continue;
    }
    sockaddr_storage peer{};
    socklen_t length = sizeof peer;
    if (getpeername(static_cast<int>(descriptor), reinterpret_cast<sockaddr*>(&peer), &length) != 0)
    {
      continue; // not a connected socket
    }
    int port = -1;
    if (peer.ss_family == AF_INET)
    {
      port = ntohs(reinterpret_cast<const sockaddr_in*>(&peer)->sin_port);
    }
    else if (peer.ss_family == AF_INET6)
    {
      port = ntohs(reinterpret_cast<const sockaddr_in6*>(&peer)->sin6_port);
    }
    if (std::find(ports.begin(), ports.end(), port) != ports.end())
    {
      shutdown(static_cast<int>(descriptor), SHUT_RDWR);
    }
  }
}

/// Shuts the viewer's sockets down if what it guards (connecting, an exchange)
/// lasts longer than `seconds`: the blocked call then returns, and ParaView's
/// link sees the error and drops the viewer (a socket timeout would not do:
/// VTK 9.2's vtkSocket::Receive adds recv's -1 to its count and tries again).
class StallGuard
{
public:
  StallGuard(double seconds, std::vector<int> ports)
  {
    if (seconds <= 0.0)
    {
      return;
    }
    this->Thread = std::thread(
        [this, seconds, ports = std::move(ports)]
        {
          std::unique_lock<std::mutex> lock(this->Mutex);
          if (!this->Done.wait_for(lock, std::chrono::duration<double>(seconds),
                                   [this] { return this->Disarmed; }))
          {
            this->Fired = true;
            shutDownSocketsTo(ports);
          }
        });
  }
  ~StallGuard() { this->disarm(); }
  StallGuard(const StallGuard&) = delete;
  StallGuard& operator=(const StallGuard&) = delete;

  /// Stops the guard; true if it had fired.
  bool disarm()
  {
    {
      std::lock_guard<std::mutex> lock(this->Mutex);
      this->Disarmed = true;
    }
    this->Done.notify_all();
    if (this->Thread.joinable())
    {
      this->Thread.join();
    }
    return this->Fired;
  }

private:
  std::mutex Mutex;
  std::condition_variable Done;
  bool Disarmed = false;
  bool Fired = false;
  std::thread Thread;
};

/// The key ParaView's link gives an extract ("group:name:port") of a source the
/// viewer asked for and the simulation does not have, from the error the link
/// logs for it ("No proxy: group, name"; it does not say the port, ParaView's
/// viewers ask for port 0).
bool missingSourceKey(const std::string& message, std::string& key)
{
  for (const char* marker : {"No proxy: ", "No vtkAlgorithm: "})
  {
    const auto at = message.find(marker);
    if (at == std::string::npos)
    {
      continue;
    }
    const auto start = at + std::string(marker).size();
    std::string groupAndName = message.substr(start, message.find('\n', start) - start);
    while (!groupAndName.empty() && std::isspace(static_cast<unsigned char>(groupAndName.back())))
    {
      groupAndName.pop_back();
    }
    const auto comma = groupAndName.find(", ");
    if (comma == std::string::npos)
    {
      return false;
    }
    key = groupAndName.substr(0, comma) + ":" + groupAndName.substr(comma + 2) + ":0";
    return true;
  }
  return false;
}

std::string seconds(double value)
{
  char text[32];
  std::snprintf(text, sizeof text, "%g s", value);
  return text;
}

} // namespace

bool LiveConnection::parseUrl(const std::string& url, Settings& settings, std::string& error)
{
  const auto colon = url.rfind(':');
  settings.host = url.substr(0, colon);
  if (settings.host.empty())
  {
    settings.host = "localhost";
  }
  if (colon == std::string::npos)
  {
    settings.port = 22222;
    return true;
  }
  const std::string port = url.substr(colon + 1);
  char* end = nullptr;
  const long value = std::strtol(port.c_str(), &end, 10);
  if (port.empty() || *end != '\0' || value < 1 || value > 65533)
  {
    error = "Catalyst Live address '" + url +
            "': the port must be a number from 1 to 65533 (the viewer also listens on the "
            "next ports, one per simulation rank it reads from)";
    return false;
  }
  settings.port = static_cast<int>(value);
  return true;
}

LiveConnection::LiveConnection(Settings settings) : Options(std::move(settings))
{
  this->Link = vtkSmartPointer<vtkLiveInsituLink>::New();
  this->Link->SetHostname(this->Options.host.c_str());
  this->Link->SetInsituPort(this->Options.port);
}

LiveConnection::~LiveConnection() = default;

bool LiveConnection::connected() const
{
  return LinkAccess::delivery(this->Link) != nullptr;
}

std::vector<std::string> LiveConnection::update(double time, std::int64_t step)
{
  std::vector<std::string> warnings;
  const SigpipeBlocked sigpipe;
  VtkMessageCapture logged;
  const QuietStderr quiet;
  if (this->connectIfListening(warnings))
  {
    const auto pauseStart = std::chrono::steady_clock::now();
    bool again = true;
    bool paused = false;
    while (again)
    {
      StallGuard guard(this->Options.stallSeconds, this->viewerPorts());
      std::vector<std::string> requestMessages;
      {
        // ParaView's link names a missing source only in an error message, which
        // VTK drops while its warnings are off (a simulation may turn them off).
        const int display = vtkObject::GetGlobalWarningDisplay();
        vtkObject::GlobalWarningDisplayOn();
        const VtkMessageCapture requests;
        this->Link->InsituUpdate(time, static_cast<vtkIdType>(step));
        requestMessages = requests.messages();
        vtkObject::SetGlobalWarningDisplay(display);
      }
      this->prepareExtracts(requestMessages, warnings);
      this->Link->InsituPostProcess(time, static_cast<vtkIdType>(step));
      if (guard.disarm())
      {
        warnings.push_back("the viewer did not answer for " + seconds(this->Options.stallSeconds) +
                           "; it was disconnected (it can connect again)");
      }
      paused = this->Link->GetSimulationPaused() != 0;
      const double pausedSeconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - pauseStart).count();
      again = paused && this->waitWhilePaused(pausedSeconds, warnings);
    }
    if (!paused)
    {
      this->PauseExpired = false;
    }
  }
  if (!this->connected())
  {
    // The viewer left: what was kept for it (a packed grid on rank 0) goes too.
    this->Substitutes.clear();
  }
  for (const auto& message : logged.messages())
  {
    std::string key;
    if (!missingSourceKey(message, key)) // said once by prepareExtracts
    {
      warnings.push_back(message);
    }
  }
  return warnings;
}

std::vector<int> LiveConnection::viewerPorts() const
{
  // Rank 0: the control port and its data port; rank r: its data port, port + 1 + r
  // (vtkLiveInsituLink::InsituConnect). Nothing else is ever shut down.
  const int rank = rankOf(ranks());
  if (rank == 0)
  {
    return {this->Options.port, this->Options.port + 1};
  }
  return {this->Options.port + 1 + rank};
}

bool LiveConnection::connectIfListening(std::vector<std::string>& warnings)
{
  if (this->connected())
  {
    return true;
  }
  // After a listener that accepted and then did not answer, the next attempts
  // wait (rank 0 decides for all: connecting is collective).
  auto* controller = ranks();
  int attempt = std::chrono::steady_clock::now() >= this->NextAttempt ? 1 : 0;
  if (controller && controller->GetNumberOfProcesses() > 1)
  {
    controller->Broadcast(&attempt, 1, 0);
  }
  if (!attempt)
  {
    return false;
  }
  // Rank 0 connects when a viewer listens (refused at once when none does);
  // the guard bounds a listener that accepts and never answers the handshake.
  StallGuard guard(this->Options.stallSeconds, this->viewerPorts());
  auto* pxm = vtkSMProxyManager::GetProxyManager()->GetActiveSessionProxyManager();
  const bool linked = this->Link->Initialize(pxm);
  if (guard.disarm() && !linked)
  {
    // The wait doubles while it keeps happening (a host that drops packets
    // holds connect() for the kernel's own timeout, which the guard cannot cut).
    const double wait = this->RetrySeconds;
    this->RetrySeconds = std::min(2.0 * this->RetrySeconds, MaximumRetrySeconds);
    this->NextAttempt = std::chrono::steady_clock::now() +
                        std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                            std::chrono::duration<double>(wait));
    warnings.push_back("something at " + this->Options.host + ":" +
                       std::to_string(this->Options.port) + " accepted the connection but did " +
                       "not answer for " + seconds(this->Options.stallSeconds) +
                       " (not a ParaView 5.11 viewer, or a stalled one); the next attempt is in " +
                       seconds(wait));
  }
  else if (linked)
  {
    this->RetrySeconds = FirstRetrySeconds;
  }
  return linked;
}

void LiveConnection::prepareExtracts(const std::vector<std::string>& requestMessages,
                                     std::vector<std::string>& warnings)
{
  auto* helper = LinkAccess::delivery(this->Link);
  if (!helper)
  {
    return;
  }
  auto warnOnce = [&](const std::string& key, const std::string& what)
  {
    if (this->Warned.insert(key).second)
    {
      warnings.push_back("the viewer asked for '" + key + "', " + what);
    }
  };
  // Rank 0 decides which sources are missing and tells the others, so that every
  // rank substitutes the same extracts (ParaView's delivery is collective).
  auto* controller = ranks();
  const int rank = rankOf(controller);
  const int size = controller ? controller->GetNumberOfProcesses() : 1;
  std::vector<std::string> missing;
  if (rank == 0)
  {
    for (const auto& message : requestMessages)
    {
      std::string key;
      if (missingSourceKey(message, key))
      {
        missing.push_back(key);
      }
    }
  }
  if (size > 1)
  {
    vtkMultiProcessStream keys;
    keys << static_cast<int>(missing.size());
    for (const auto& key : missing)
    {
      keys << key;
    }
    controller->Broadcast(keys, 0);
    int count = 0;
    keys >> count;
    missing.resize(static_cast<std::size_t>(count));
    for (auto& key : missing)
    {
      keys >> key;
    }
  }
  auto& producers = DeliveryAccess::producers(helper);
  for (const auto& key : missing)
  {
    auto& substitute = this->Substitutes[key];
    if (!vtkTrivialProducer::SafeDownCast(substitute))
    {
      auto empty = vtkSmartPointer<vtkTrivialProducer>::New();
      empty->SetOutput(vtkSmartPointer<vtkPolyData>::New());
      substitute = empty;
    }
    producers[key] = substitute->GetOutputPort();
    warnOnce(key, "which this simulation does not have: it gets an empty vtkPolyData (ParaView's "
                  "viewer shows nothing new until every extract it asked for arrives)");
  }
  for (auto& entry : producers)
  {
    vtkAlgorithmOutput* port = entry.second;
    vtkAlgorithm* algorithm = port ? port->GetProducer() : nullptr;
    if (algorithm &&
        vtkHyperTreeGrid::SafeDownCast(algorithm->GetOutputDataObject(port->GetIndex())))
    {
      auto* packer = vtkCanopyHyperTreeGridPacker::SafeDownCast(this->Substitutes[entry.first]);
      if (!packer)
      {
        auto created = vtkSmartPointer<vtkCanopyHyperTreeGridPacker>::New();
        this->Substitutes[entry.first] = created;
        packer = created;
      }
      packer->SetController(controller);
      packer->SetInputConnection(port);
      entry.second = packer->GetOutputPort();
      algorithm = packer;
      warnOnce(
          entry.first,
          "a hypertree grid, which VTK 9.2 cannot send: it is sent packed; apply Canopy Unpack "
          "Grid to it in the viewer (docs/insitu.md, Catalyst Live)");
    }
    if (auto* packer = vtkCanopyHyperTreeGridPacker::SafeDownCast(algorithm))
    {
      // Executed on every rank at every exchange, never skipped by one rank as
      // up to date: its gather is collective.
      packer->Modified();
    }
    if (algorithm)
    {
      // ParaView sends the output as it is; a filter no image needed this step
      // would send last step's data, or none. Collective for the packer: every
      // rank walks the same requests in the same (key) order.
      algorithm->UpdatePiece(rank, size, 0);
    }
  }
}

bool LiveConnection::waitWhilePaused(double pausedSeconds, std::vector<std::string>& warnings)
{
  auto* controller = ranks();
  int decision = 0; // 1: the viewer sent something; 0: go on
  if (rankOf(controller) == 0 && !this->PauseExpired)
  {
    const int socket = descriptorOf(LinkAccess::control(this->Link));
    const double limit = this->Options.pauseLimitSeconds;
    const auto start = std::chrono::steady_clock::now();
    while (socket >= 0)
    {
      const double waited =
          pausedSeconds +
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      if (limit > 0.0 && waited >= limit)
      {
        warnings.push_back("paused by the viewer for " + seconds(limit) +
                           " (the pause limit): the simulation goes on");
        this->PauseExpired = true;
        break;
      }
      const double slice = limit > 0.0 ? std::min(0.25, limit - waited) : 0.25;
      int selected = -1;
      const int ready = vtkSocket::SelectSockets(
          &socket, 1, static_cast<unsigned long>(slice * 1000.0) + 1, &selected);
      if (ready != 0)
      {
        decision = ready > 0 ? 1 : 0;
        break;
      }
    }
  }
  if (controller && controller->GetNumberOfProcesses() > 1)
  {
    controller->Broadcast(&decision, 1, 0);
  }
  if (decision != 1)
  {
    return false;
  }
  StallGuard guard(this->Options.stallSeconds, this->viewerPorts());
  return this->Link->WaitForLiveChange() == 0;
}

} // namespace canopy
