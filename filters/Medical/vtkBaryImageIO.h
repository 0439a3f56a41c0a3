/**
 * @class   vtkBaryImageIO
 * @brief   Reads and writes medical images (NIfTI, NRRD, MetaImage) through ITK, with their
 *          geometry in LPS and errors as exceptions.
 *
 * Formats, by file extension: NIfTI `.nii`, `.nii.gz`; NRRD `.nrrd` (and `.nhdr` with a detached
 * data file, reading only); MetaImage `.mha`, `.mhd` (with its `.raw` / `.zraw` data file). The
 * reading and writing are ITK's own (Debian's ITK 5.2: itk::NiftiImageIO, itk::NrrdImageIO,
 * itk::MetaImageIO, the image IO classes behind itk::ImageFileReader/Writer), so a file written
 * here is what ITK and 3D Slicer read, and a file they write is read with the geometry they see.
 *
 * Geometry: ITK's physical space, **LPS, in millimetres**: a voxel with index (i, j, k) lies at
 * origin + D · (i sx, j sy, k sz), D the 3 x 3 direction matrix (columns: the index axes'
 * directions), s the spacing. Read() returns a vtkImageData with that origin, spacing and
 * direction (vtkImageData::SetDirectionMatrix; extent from 0); NIfTI stores RAS on disk and ITK
 * converts its qform/sform to LPS (x and y negated), NRRD and MetaImage store LPS. A 2-D image
 * is read as one slice (direction embedded in the 3 x 3 matrix, third axis +z); 4-D and larger
 * images are read only when their extra axes have one sample (a NIfTI vector field of another
 * intent than NIFTI_INTENT_VECTOR, e.g. 1006, which ITK 5.2 reads as a 5-D scalar image, is
 * refused with that reason).
 *
 * Voxel values keep their type and components (a label map stays integer); the array is the
 * image's point scalars, named "ImageScalars". NIfTI scaling (scl_slope / scl_inter) is applied
 * by ITK, which then returns float.
 *
 * Write() takes a vtkImageData with point scalars of one component (any numeric type but bit)
 * or three (a vector image: displacement fields, written with ITK's vector pixel type so that
 * ITK reads it as itk::Image<itk::Vector<double, 3>, 3>, as ITK's displacement-field transforms
 * and Slicer's grid transforms take it: NIfTI gets intent NIFTI_INTENT_VECTOR (1007) and the 5-D
 * layout dim = (5, nx, ny, nz, 1, 3), NRRD `kinds: vector domain domain domain`, MetaImage
 * `ElementNumberOfChannels = 3`). The vector components are written as given: they are not
 * converted between LPS and RAS in any format (ITK 5.2 does not either). The image's own
 * direction matrix and origin are written (an extent not starting at 0 moves the origin to the
 * first voxel; a direction column that is not of unit length is written as a unit column with
 * its length folded into that axis' spacing: the same physical points). A non-orthogonal but
 * invertible direction is kept by NRRD and MetaImage; NIfTI's qform holds a rotation only.
 * `.nii.gz`, `.nrrd`, `.mha` and `.mhd` are gzip-compressed. NIfTI files that end before
 * their voxels do (which NIfTI's library would fill with zeros) and MetaImage data blocks that
 * are cut short are refused.
 * Writing is atomic: the file (and a `.mhd`'s data file) is written into a temporary folder
 * beside the target and renamed into place only when complete, so a failed write leaves no
 * file, partial or temporary, behind.
 *
 * Errors: bary::Error(Io) naming the file and the problem (missing, not a regular file, an
 * unknown extension, content ITK cannot read, a missing folder on writing, ITK's own message),
 * (InvalidArgument) for an image that cannot be written (no scalars, 2 or 4+ components, a
 * non-positive or non-finite spacing, a non-finite or singular direction, a non-finite origin).
 *
 * ITK's headers are included by vtkBaryImageIO.cxx only (they are slow to compile); ITK is a
 * private dependency of BaryLab::BaryLabMedical.
 */
#ifndef vtkBaryImageIO_h
#define vtkBaryImageIO_h

#include "BaryLabMedicalModule.h" // for export macro
#include "vtkObject.h"
#include "vtkSmartPointer.h" // for vtkSmartPointer

#include <string> // for std::string

class vtkImageData;

class BARYLABMEDICAL_EXPORT vtkBaryImageIO : public vtkObject
{
public:
  static vtkBaryImageIO* New();
  vtkTypeMacro(vtkBaryImageIO, vtkObject);

  /// Reads the image @p path (format by extension) with its LPS geometry and typed voxels.
  /// @throws bary::Error(Io) naming the file and the problem.
  static vtkSmartPointer<vtkImageData> Read(const std::string& path);
  /// Writes @p image to @p path (format by extension), atomically.
  /// @throws bary::Error(Io) naming the file, (InvalidArgument) for an image that cannot be
  ///   written.
  static void Write(vtkImageData* image, const std::string& path);
  /// Lower-case extension of @p path including the dot, ".nii.gz" as one (".nrrd"), or "".
  static std::string Extension(const std::string& path);
  /// True if Read() understands the extension of @p path (.nii, .nii.gz, .nrrd, .nhdr, .mha,
  /// .mhd).
  static bool CanRead(const std::string& path);
  /// True if Write() knows the extension of @p path (.nii, .nii.gz, .nrrd, .mha, .mhd).
  static bool CanWrite(const std::string& path);

protected:
  vtkBaryImageIO() = default;
  ~vtkBaryImageIO() override = default;

private:
  vtkBaryImageIO(const vtkBaryImageIO&) = delete;
  void operator=(const vtkBaryImageIO&) = delete;
};

#endif
