/**
 * @class   vtkBaryErrorObserver
 * @brief   Records the error and warning messages of algorithms instead of printing them.
 *
 * Attach it with Observe(algorithm): it listens to ErrorEvent and WarningEvent on the algorithm
 * and ErrorEvent on its executive (which repeats every failure as "Algorithm ... returned
 * failure for request"). The messages are kept without VTK's "ERROR: In file, line N /
 * vtkClass (0x...): " prefix. Used by vtkBaryDataIO and the command line to turn VTK errors
 * into one readable line.
 */
#ifndef vtkBaryErrorObserver_h
#define vtkBaryErrorObserver_h

#include "BaryLabFiltersModule.h" // for export macro
#include "vtkCommand.h"

#include <functional> // for std::function
#include <string>     // for std::string
#include <vector>     // for std::vector

class vtkAlgorithm;

class BARYLABFILTERS_EXPORT vtkBaryErrorObserver : public vtkCommand
{
public:
  static vtkBaryErrorObserver* New();
  vtkBaseTypeMacro(vtkBaryErrorObserver, vtkCommand);

  void Execute(vtkObject* caller, unsigned long event, void* data) override;

  /// Listen to @p algorithm (errors, warnings) and its executive (errors).
  void Observe(vtkAlgorithm* algorithm);
  /// Stop listening to everything Observe() attached.
  void Release();

  /// The first error message since the last Clear(), or "".
  const std::string& GetFirstError() const { return this->FirstError; }
  bool HasError() const { return !this->FirstError.empty(); }
  /// All warnings since the last Clear().
  const std::vector<std::string>& GetWarnings() const { return this->Warnings; }
  /// Called for each warning as it arrives (optional).
  std::function<void(const std::string&)> WarningCallback;
  void Clear();

  /// VTK's message without its "ERROR: In file, line N\nvtkClass (0x...): " prefix and trailing
  /// white space.
  static std::string CleanMessage(const std::string& message);

protected:
  vtkBaryErrorObserver() = default;
  ~vtkBaryErrorObserver() override;

private:
  std::string FirstError;
  std::vector<std::string> Warnings;
  struct Tag
  {
    vtkObject* Object;
    unsigned long Id;
  };
  std::vector<Tag> Tags;
};

#endif
