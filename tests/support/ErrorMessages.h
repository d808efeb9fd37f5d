// The error messages an algorithm reports while it runs (VTK's ErrorEvent),
// so a test can check both that it failed and what it said.
#pragma once

#include <vtkAlgorithm.h>
#include <vtkCallbackCommand.h>
#include <vtkCommand.h>
#include <vtkNew.h>

#include <string>
#include <vector>

namespace canopy::testing
{

/// Runs algorithm->Update() and returns the messages of the errors it reported.
inline std::vector<std::string> errorsOfUpdate(vtkAlgorithm* algorithm)
{
  std::vector<std::string> messages;
  vtkNew<vtkCallbackCommand> onError;
  onError->SetClientData(&messages);
  onError->SetCallback(
      [](vtkObject*, unsigned long, void* data, void* text)
      {
        static_cast<std::vector<std::string>*>(data)->emplace_back(
            text ? static_cast<const char*>(text) : "");
      });
  const unsigned long tag = algorithm->AddObserver(vtkCommand::ErrorEvent, onError);
  algorithm->Update();
  algorithm->RemoveObserver(tag);
  return messages;
}

} // namespace canopy::testing
