#include "vtkBaryErrorObserver.h"

#include "vtkAlgorithm.h"
#include "vtkExecutive.h"

#include <cctype>

vtkBaryErrorObserver* vtkBaryErrorObserver::New()
{
  return new vtkBaryErrorObserver;
}

vtkBaryErrorObserver::~vtkBaryErrorObserver()
{
  // Nothing to remove: an observer is destroyed only once every object it observed has let go
  // of it (AddObserver holds a reference), and removing it from an object being destroyed
  // (an exception unwinding past Release) recursed until the stack overflowed.
  this->Tags.clear();
}

std::string vtkBaryErrorObserver::CleanMessage(const std::string& message)
{
  std::string text = message;
  // "ERROR: In /path/file.cxx, line 123\nvtkClass (0x55d0c0ffee00): the message"
  const auto object = text.find(" (0x");
  if (object != std::string::npos)
  {
    const auto colon = text.find("): ", object);
    if (colon != std::string::npos)
      text = text.substr(colon + 3);
  }
  while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back())))
    text.pop_back();
  return text;
}

void vtkBaryErrorObserver::Execute(vtkObject*, unsigned long event, void* data)
{
  if (!data)
    return;
  const std::string text = CleanMessage(static_cast<const char*>(data));
  if (event == vtkCommand::ErrorEvent)
  {
    if (this->FirstError.empty())
      this->FirstError = text;
  }
  else if (event == vtkCommand::WarningEvent)
  {
    this->Warnings.push_back(text);
    if (this->WarningCallback)
      this->WarningCallback(text);
  }
}

void vtkBaryErrorObserver::Observe(vtkAlgorithm* algorithm)
{
  if (!algorithm)
    return;
  this->Tags.push_back({ algorithm, algorithm->AddObserver(vtkCommand::ErrorEvent, this) });
  this->Tags.push_back({ algorithm, algorithm->AddObserver(vtkCommand::WarningEvent, this) });
  if (vtkExecutive* executive = algorithm->GetExecutive())
    this->Tags.push_back({ executive, executive->AddObserver(vtkCommand::ErrorEvent, this) });
}

void vtkBaryErrorObserver::Release()
{
  for (const Tag& tag : this->Tags)
    tag.Object->RemoveObserver(tag.Id);
  this->Tags.clear();
}

void vtkBaryErrorObserver::Clear()
{
  this->FirstError.clear();
  this->Warnings.clear();
}
