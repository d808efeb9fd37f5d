#include "CatalystScript.h"

#include "DriverPython.h"

#include <vtkCPDataDescription.h>
#include <vtkCPInputDataDescription.h>
#include <vtkCPPythonScriptV2Helper.h>
#include <vtkDataObject.h>

#include <cmath>
#include <stdexcept>

namespace canopy
{

CatalystScript::CatalystScript(std::string path, const std::string& channel)
    : Path(std::move(path)), Channel(channel)
{
  this->Description->AddInput(channel.c_str());
  if (!this->Helper->PrepareFromScript(this->Path))
  {
    throw std::runtime_error("Catalyst cannot load the script '" + this->Path +
                             "' (see the Python message above)");
  }
}

CatalystScript::~CatalystScript() = default;

CatalystScript::Request CatalystScript::request(std::int64_t step, double time, std::string& error)
{
  this->Description->SetTimeData(time, static_cast<vtkIdType>(step));
  this->Description->ResetInputDescriptions();
  if (this->Disabled)
  {
    return Request::NotDue;
  }
  if (!this->Imported)
  {
    auto* input = this->Description->GetInputDescriptionByName(this->Channel.c_str());
    input->AllFieldsOn();
    input->GenerateMeshOn();
    return Request::Due;
  }
  return this->requestAfterImport(error);
}

CatalystScript::Request CatalystScript::requestAfterImport(std::string& error)
{
  auto* input = this->Description->GetInputDescriptionByName(this->Channel.c_str());
  input->GenerateMeshOff();
  input->AllFieldsOff();
  if (!this->Helper->RequestDataDescription(this->Description))
  {
    error = "the script '" + this->Path +
            "' failed in RequestDataDescription: " + this->pythonProblem();
    return Request::Failed;
  }
  return this->Description->GetIfAnyGridNecessary() ? Request::Due : Request::NotDue;
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
  const bool ok = this->Helper->Import(this->Description) &&
                  this->Helper->CatalystInitialize(this->Description);
  this->Description->SetTimeData(time, step);
  input->SetGrid(nullptr);
  this->Imported = ok;
  if (!ok)
  {
    error = "the script '" + this->Path + "' failed to import (" + this->pythonProblem() + ")";
  }
  return ok;
}

bool CatalystScript::run(vtkDataObject* grid, std::string& error)
{
  auto* input = this->Description->GetInputDescriptionByName(this->Channel.c_str());
  input->SetGrid(grid);
  const bool ok = this->Helper->CatalystExecute(this->Description);
  // Do not keep the simulation's memory referenced from the description.
  input->SetGrid(nullptr);
  if (!ok)
  {
    error = "the script '" + this->Path + "' " + this->pythonProblem();
  }
  return ok;
}

bool CatalystScript::finalize(std::string& error)
{
  if (!this->Imported || this->Disabled)
  {
    return true;
  }
  if (!this->Helper->CatalystFinalize())
  {
    error = "the script '" + this->Path + "' failed in catalyst_finalize: " + this->pythonProblem();
    return false;
  }
  return true;
}

std::string CatalystScript::pythonProblem()
{
  auto failure = takeScriptFailure();
  this->LastTraceback = std::move(failure.traceback);
  return failure.summary.empty() ? "raised an error (Python message above)" : failure.summary;
}

} // namespace canopy
