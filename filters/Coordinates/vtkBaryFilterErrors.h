/**
 * @file   vtkBaryFilterErrors.h
 * @brief  Internal: the one way BaryLab filters turn exceptions into VTK errors.
 *
 * Every filter's RequestData runs its work in `try { ... } VTKBARY_CATCH_ERRORS` (in a member
 * function returning int): a bary::Error keeps its kind in the algorithm's error code
 * (vtkBaryConversion::ToVTKErrorCode, read back with ErrorCodeOf) and its message goes to
 * vtkErrorMacro; any other exception is reported as an internal failure. Both return 0. A macro
 * because vtkAlgorithm::SetErrorCode is protected and vtkErrorMacro needs `this`.
 */
#ifndef vtkBaryFilterErrors_h
#define vtkBaryFilterErrors_h

#include "vtkBaryConversion.h"

#include "core/common/error.h"

#include <exception>

#define VTKBARY_CATCH_ERRORS                                                                       \
  catch (const bary::Error& e)                                                                     \
  {                                                                                                \
    this->SetErrorCode(vtkBaryConversion::ToVTKErrorCode(e.code()));                               \
    vtkErrorMacro(<< e.what());                                                                    \
    return 0;                                                                                      \
  }                                                                                                \
  catch (const std::exception& e)                                                                  \
  {                                                                                                \
    this->SetErrorCode(vtkBaryConversion::ToVTKErrorCode(bary::ErrorCode::Internal));              \
    vtkErrorMacro(<< "Unexpected failure: " << e.what());                                          \
    return 0;                                                                                      \
  }

#endif
