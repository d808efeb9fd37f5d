#include "CatalystScript.h"

#include "CanopyModule.h"
#include "StepWatchdog.h"
#include "VtkMessageCapture.h"

#include <vtkCPDataDescription.h>
#include <vtkCPInputDataDescription.h>
#include <vtkCPPythonScriptV2Helper.h>
#include <vtkDataObject.h>
#include <vtkSMExtractTriggerProxy.h>
#include <vtkSMExtractsController.h>
#include <vtkSMPropertyHelper.h>
#include <vtkSMProxy.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace canopy
{

CatalystScript::CatalystScript(std::string path, const std::string& channel, StepWatchdog& watchdog)
    : Path(std::move(path)), Channel(channel), Watchdog(watchdog)
{
  this->Description->AddInput(channel.c_str());
  if (!this->Helper->PrepareFromScript(this->Path))
  {
    throw std::runtime_error("Catalyst cannot load the script '" + this->Path +
                             "' (see the Python message above)");
  }
}

CatalystScript::~CatalystScript() = default;

double CatalystScript::extraSeconds() const
{
  return this->Imported && !this->FirstRun ? 0.0 : StepWatchdog::firstStepExtraSeconds;
}

std::string CatalystScript::when() const
{
  return "step " + std::to_string(this->Description->GetTimeStep());
}

std::string CatalystScript::failure(bool exceeded)
{
  auto python = PythonSide::takeFailure();
  this->LastTraceback = std::move(python.traceback);
  if (!python.summary.empty())
  {
    return python.summary;
  }
  return exceeded ? "exceeded " + this->Watchdog.limitText()
                  : "raised an error (Python message above)";
}

template <typename Call>
bool CatalystScript::watched(const char* call, bool& exceeded, Call&& body)
{
  // The watch ends before the failure is read: reading it runs Python, which
  // the watchdog must not interrupt.
  const bool closing = std::string(call) == "catalyst_finalize";
  const auto watch = this->Watchdog.watch(this->Path, call, closing ? "close" : this->when(),
                                          this->extraSeconds());
  const bool ok = body();
  exceeded = watch.exceeded();
  return ok && !exceeded;
}

ScriptState CatalystScript::request(std::int64_t step, double time, std::string& error)
{
  this->Description->SetTimeData(time, static_cast<vtkIdType>(step));
  this->Description->ResetInputDescriptions();
  if (this->Disabled)
  {
    return ScriptState::NotDue;
  }
  if (!this->Imported)
  {
    auto* input = this->Description->GetInputDescriptionByName(this->Channel.c_str());
    input->AllFieldsOn();
    input->GenerateMeshOn();
    return ScriptState::Due;
  }
  return this->requestAfterImport(error);
}

ScriptState CatalystScript::requestAfterImport(std::string& error)
{
  auto* input = this->Description->GetInputDescriptionByName(this->Channel.c_str());
  input->GenerateMeshOff();
  input->AllFieldsOff();
  bool exceeded = false;
  const bool ok =
      this->watched("RequestDataDescription", exceeded,
                    [&] { return this->Helper->RequestDataDescription(this->Description); });
  if (!ok)
  {
    error = "the script '" + this->Path +
            "' failed in RequestDataDescription: " + this->failure(exceeded);
    return ScriptState::Failed;
  }
  if (this->Description->GetIfAnyGridNecessary())
  {
    return ScriptState::Due;
  }
  // ParaView counts a script with Live on as due at its Live trigger's steps; its
  // Live is Canopy's now (takeOverLive), so Canopy asks that trigger itself: a
  // script whose only consumer is a Live viewer still runs, with every field.
  if (this->liveTriggered())
  {
    input->GenerateMeshOn();
    input->AllFieldsOn();
    return ScriptState::Due;
  }
  return ScriptState::NotDue;
}

bool CatalystScript::liveTriggered() const
{
  auto* trigger = vtkSMExtractTriggerProxy::SafeDownCast(this->LiveTrigger);
  if (this->LiveUrl.empty() || trigger == nullptr)
  {
    return false;
  }
  vtkNew<vtkSMExtractsController> controller;
  controller->SetTimeStep(static_cast<int>(this->Description->GetTimeStep()));
  controller->SetTime(this->Description->GetTime());
  return trigger->IsActivated(controller);
}

bool CatalystScript::needsAllFields() const
{
  auto* input = this->Description->GetInputDescriptionByName(this->Channel.c_str());
  return input->GetAllFields();
}

bool CatalystScript::needsField(const std::string& name) const
{
  // Asked by name: ParaView 5.11's GetFieldName(i) returns the c_str() of a copy
  // destroyed before it returns (names over 15 characters come back as garbage).
  auto* input = this->Description->GetInputDescriptionByName(this->Channel.c_str());
  for (int association : {vtkDataObject::CELL, vtkDataObject::POINT, vtkDataObject::FIELD})
  {
    if (input->IsFieldNeeded(name.c_str(), association))
    {
      return true;
    }
  }
  return false;
}

unsigned int CatalystScript::numberOfNeededFields() const
{
  return this->Description->GetInputDescriptionByName(this->Channel.c_str())->GetNumberOfFields();
}

bool CatalystScript::import(vtkDataObject* grid, std::string& error)
{
  // As ParaView's V2 pipeline does: import with the grid present, so that the
  // script's module-level code can build its pipeline on real data.
  auto* input = this->Description->GetInputDescriptionByName(this->Channel.c_str());
  input->SetGrid(grid);
  // ParaView's producer is created at import with the description's time, and
  // the run of the same step sets it again: a time not after the last one makes
  // it warn. Import just before the step's time (one ulp) so the run's is later.
  const double time = this->Description->GetTime();
  const vtkIdType step = this->Description->GetTimeStep();
  this->Description->SetTimeData(std::nextafter(time, -HUGE_VAL), step);
  bool exceeded = false;
  const bool ok = this->watched("import", exceeded,
                                [&]
                                {
                                  return this->Helper->Import(this->Description) &&
                                         this->Helper->CatalystInitialize(this->Description);
                                });
  if (!ok)
  {
    error = "the script '" + this->Path + "' failed to import (" + this->failure(exceeded) + ")";
  }
  this->Description->SetTimeData(time, step);
  input->SetGrid(nullptr);
  this->takeOverLive();
  this->Imported = ok;
  this->FirstRun = ok;
  return ok;
}

bool CatalystScript::run(vtkDataObject* grid, std::string& error)
{
  auto* input = this->Description->GetInputDescriptionByName(this->Channel.c_str());
  input->SetGrid(grid);
  bool exceeded = false;
  VtkMessageCapture logged;
  bool ok = this->watched("catalyst_execute", exceeded,
                          [&] { return this->Helper->CatalystExecute(this->Description); });
  this->FirstRun = false;
  const auto messages = logged.messages();
  if (!ok)
  {
    error = "the script '" + this->Path + "' " + this->failure(exceeded);
  }
  else if (!messages.empty())
  {
    // A writer's error (full disk, a file it cannot open) or any warning: the
    // step's extracts cannot be trusted.
    this->LastTraceback.clear();
    std::string first = messages.front();
    std::replace(first.begin(), first.end(), '\n', ' ');
    error = "the script '" + this->Path + "' logged an error: " + first +
            (messages.size() > 1 ? " (and " + std::to_string(messages.size() - 1) + " more)"
                                 : std::string());
    ok = false;
  }
  // Do not keep the simulation's memory referenced from the description.
  input->SetGrid(nullptr);
  return ok;
}

void CatalystScript::takeOverLive()
{
  vtkSMProxy* options = this->Helper->GetOptions();
  if (!options || !options->GetProperty("EnableCatalystLive") ||
      vtkSMPropertyHelper(options, "EnableCatalystLive").GetAsInt() == 0)
  {
    return;
  }
  const char* url = vtkSMPropertyHelper(options, "CatalystLiveURL").GetAsString();
  this->LiveUrl = url && *url ? url : "localhost:22222";
  this->LiveTrigger = vtkSMPropertyHelper(options, "CatalystLiveTrigger").GetAsProxy();
  vtkSMPropertyHelper(options, "EnableCatalystLive").Set(0);
  options->UpdateVTKObjects();
}

void CatalystScript::discardOutputs()
{
  PythonSide::discardOutputs(this->Path);
}

bool CatalystScript::finalize(std::string& error)
{
  if (!this->Imported || this->Disabled)
  {
    return true;
  }
  bool exceeded = false;
  if (!this->watched("catalyst_finalize", exceeded,
                     [&] { return this->Helper->CatalystFinalize(); }))
  {
    error =
        "the script '" + this->Path + "' failed in catalyst_finalize: " + this->failure(exceeded);
    return false;
  }
  return true;
}

} // namespace canopy
