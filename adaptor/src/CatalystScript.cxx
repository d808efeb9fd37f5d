#include "CatalystScript.h"

#include <vtkCPDataDescription.h>
#include <vtkCPInputDataDescription.h>
#include <vtkCPPythonScriptV2Helper.h>
#include <vtkDataObject.h>

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
  auto* input = this->Description->GetInputDescriptionByName(this->Channel.c_str());
  input->GenerateMeshOff();
  input->AllFieldsOff();
  if (this->ImportFailed)
  {
    error = "the script '" + this->Path + "' failed to import earlier";
    return Request::Failed;
  }
  if (!this->Imported)
  {
    input->AllFieldsOn();
    input->GenerateMeshOn();
    return Request::Due;
  }
  if (!this->Helper->RequestDataDescription(this->Description))
  {
    error = "Python error in RequestDataDescription of '" + this->Path + "'";
    return Request::Failed;
  }
  return this->Description->GetIfAnyGridNecessary() ? Request::Due : Request::NotDue;
}

bool CatalystScript::needsAllFields() const
{
  auto* input = this->Description->GetInputDescriptionByName(this->Channel.c_str());
  return input->GetAllFields();
}

std::vector<std::string> CatalystScript::neededFields() const
{
  auto* input = this->Description->GetInputDescriptionByName(this->Channel.c_str());
  std::vector<std::string> names;
  for (unsigned int i = 0; i < input->GetNumberOfFields(); ++i)
  {
    names.emplace_back(input->GetFieldName(i));
  }
  return names;
}

CatalystScript::Outcome CatalystScript::execute(vtkDataObject* grid, std::string& error)
{
  auto* input = this->Description->GetInputDescriptionByName(this->Channel.c_str());
  input->SetGrid(grid);
  Outcome outcome = Outcome::Ran;
  if (!this->Imported)
  {
    // The first run imports the script with the grid present, as ParaView's
    // V2 pipeline does, then asks it whether it is due at all.
    if (!this->Helper->Import(this->Description) ||
        !this->Helper->CatalystInitialize(this->Description))
    {
      this->ImportFailed = true;
      error = "the script '" + this->Path + "' failed to import (Python message above)";
      input->SetGrid(nullptr);
      return Outcome::Failed;
    }
    this->Imported = true;
    input->GenerateMeshOff();
    input->AllFieldsOff();
    if (!this->Helper->RequestDataDescription(this->Description))
    {
      error = "Python error in RequestDataDescription of '" + this->Path + "'";
      outcome = Outcome::Failed;
    }
    else if (!this->Description->GetIfAnyGridNecessary())
    {
      outcome = Outcome::NotDue;
    }
  }
  if (outcome == Outcome::Ran && !this->Helper->CatalystExecute(this->Description))
  {
    error = "the script '" + this->Path + "' raised an error (Python message above)";
    outcome = Outcome::Failed;
  }
  // Do not keep the simulation's memory referenced between steps.
  input->SetGrid(nullptr);
  return outcome;
}

void CatalystScript::finalize()
{
  if (this->Imported)
  {
    this->Helper->CatalystFinalize();
  }
}

} // namespace canopy
