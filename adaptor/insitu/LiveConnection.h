// Catalyst Live for Canopy's scripts (docs/insitu.md, "Catalyst Live"), run by
// Canopy after the step's scripts instead of inside ParaView's V2 helper
// (vtkCPPythonScriptV2Helper::DoLive), so that a viewer cannot hurt the
// simulation:
// - an extract of a hypertree grid, which VTK 9.2 cannot send ("Cannot send
//   vtkHyperTreeGrid", then every step failed), is sent packed
//   (vtkCanopyHyperTreeGridPacker; the viewer applies Canopy Unpack Grid);
// - an extract of a source the simulation does not have is sent as an empty
//   vtkPolyData: ParaView's viewer refreshes nothing until every extract it
//   asked for arrived (vtkExtractsDeliveryHelper::Update), so one missing name
//   would otherwise stop every delivery;
// - every extract a viewer pulls is brought up to date before it is sent
//   (ParaView sends whatever was last computed, often nothing);
// - a viewer that stops answering is dropped after `stallSeconds` (timeouts on
//   the sockets; ParaView would wait forever);
// - a pause lasts at most `pauseLimitSeconds`, then the simulation goes on and
//   ignores that pause (a forgotten viewer does not hold a job);
// - whatever Live logs becomes a warning of the step, never its failure.
// ParaView's own link (vtkLiveInsituLink) still speaks the protocol, so ParaView
// 5.11's GUI (Catalyst > Connect) and pvpython (paraview.live) are the viewers.
#pragma once

#include <vtkSmartPointer.h>

#include <chrono>
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>

class vtkAlgorithm;
class vtkLiveInsituLink;

namespace canopy
{

class LiveConnection
{
public:
  struct Settings
  {
    std::string host = "localhost"; ///< where the viewer listens (Catalyst > Connect)
    int port = 22222;
    double pauseLimitSeconds = 300.0; ///< <= 0: a pause lasts until the viewer resumes
    double stallSeconds = 10.0;       ///< a viewer silent this long is dropped
  };

  /// Parses "host:port" (or "host", port 22222); false with `error` if unusable.
  static bool parseUrl(const std::string& url, Settings& settings, std::string& error);

  explicit LiveConnection(Settings settings);
  ~LiveConnection();
  LiveConnection(const LiveConnection&) = delete;
  LiveConnection& operator=(const LiveConnection&) = delete;

  /// One Live exchange after the step's scripts ran: connects if a viewer
  /// listens, takes its changes and requests, sends the extracts, waits while
  /// paused. Collective over Catalyst's ranks. Returns this rank's warnings.
  std::vector<std::string> update(double time, std::int64_t step);

  const Settings& settings() const { return this->Options; }
  /// Whether a viewer was connected at the end of the last update (rank 0's view).
  bool connected() const;

private:
  /// Connected, or connects if a viewer listens (collective). A listener that
  /// accepts and does not answer within stallSeconds is left, with a warning,
  /// and not tried again for a minute (doubling each time it happens again).
  bool connectIfListening(std::vector<std::string>& warnings);
  /// The viewer's ports this rank talks to (the stall guard's targets).
  std::vector<int> viewerPorts() const;
  /// Makes every extract the viewer asked for sendable and up to date.
  /// `requestMessages`: what ParaView's link logged while reading the requests
  /// (its "No proxy: group, name" errors name the missing sources).
  void prepareExtracts(const std::vector<std::string>& requestMessages,
                       std::vector<std::string>& warnings);
  /// While paused: true when the viewer sent something (then the exchange runs
  /// again), false when the pause is over, the viewer left or the limit passed.
  bool waitWhilePaused(double pausedSeconds, std::vector<std::string>& warnings);

  Settings Options;
  vtkSmartPointer<vtkLiveInsituLink> Link;
  /// What is sent instead of an unsendable or missing extract, by key
  /// ("group:name:port"), kept while a viewer is connected.
  std::map<std::string, vtkSmartPointer<vtkAlgorithm>> Substitutes;
  std::set<std::string> Warned; ///< extracts already warned about
  bool PauseExpired = false;
  static constexpr double FirstRetrySeconds = 60.0;
  static constexpr double MaximumRetrySeconds = 3600.0;
  double RetrySeconds = FirstRetrySeconds;
  std::chrono::steady_clock::time_point NextAttempt{};
};

} // namespace canopy
