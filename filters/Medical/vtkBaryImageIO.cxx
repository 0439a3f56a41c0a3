#include "vtkBaryImageIO.h"

#include "core/common/error.h"

#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkMath.h"
#include "vtkMatrix3x3.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"
#include "vtkType.h"

// The only ITK headers of BaryLab (slow to compile: keep them in this file). The image IO
// classes are used directly, without itk::ImageFileReader/Writer's pixel-type templates (one
// instantiation per pixel type would multiply this file's compile time); they are what those
// classes call, and chosen by extension rather than through ITK's factory registration.
#include "itkImageIOBase.h"
#include "itkMetaImageIO.h"
#include "itkNiftiImageIO.h"
#include "itkNrrdImageIO.h"
#include "znzlib.h" // ITK's NIfTI file layer (gzip or plain): the completeness check of a .nii

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstdint>
#include <cstring>
#include <dirent.h>
#include <iostream>
#include <sstream>
#include <string>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

vtkStandardNewMacro(vtkBaryImageIO);

namespace
{
using bary::Error;
using bary::ErrorCode;
using Component = itk::IOComponentEnum;
using PixelKind = itk::IOPixelEnum;

/// The ITK image IO of @p ext, or null.
itk::ImageIOBase::Pointer image_io_for(const std::string& ext)
{
  if (ext == ".nii" || ext == ".nii.gz")
    return itk::NiftiImageIO::New().GetPointer();
  if (ext == ".nrrd" || ext == ".nhdr")
    return itk::NrrdImageIO::New().GetPointer();
  if (ext == ".mha" || ext == ".mhd")
    return itk::MetaImageIO::New().GetPointer();
  return nullptr;
}

int vtk_type_of(Component c)
{
  switch (c)
  {
    case Component::UCHAR: return VTK_UNSIGNED_CHAR;
    case Component::CHAR: return VTK_SIGNED_CHAR;
    case Component::USHORT: return VTK_UNSIGNED_SHORT;
    case Component::SHORT: return VTK_SHORT;
    case Component::UINT: return VTK_UNSIGNED_INT;
    case Component::INT: return VTK_INT;
    case Component::ULONG: return VTK_UNSIGNED_LONG;
    case Component::LONG: return VTK_LONG;
    case Component::ULONGLONG: return VTK_UNSIGNED_LONG_LONG;
    case Component::LONGLONG: return VTK_LONG_LONG;
    case Component::FLOAT: return VTK_FLOAT;
    case Component::DOUBLE: return VTK_DOUBLE;
    default: return -1;
  }
}

/// ITK's component type for VTK's @p type, with @p ok false where there is none.
Component itk_type_of(int type, bool& ok)
{
  ok = true;
  switch (type)
  {
    case VTK_UNSIGNED_CHAR: return Component::UCHAR;
    case VTK_CHAR: // char is signed on the platforms BaryLab builds on
    case VTK_SIGNED_CHAR: return Component::CHAR;
    case VTK_UNSIGNED_SHORT: return Component::USHORT;
    case VTK_SHORT: return Component::SHORT;
    case VTK_UNSIGNED_INT: return Component::UINT;
    case VTK_INT: return Component::INT;
    case VTK_UNSIGNED_LONG: return Component::ULONG;
    case VTK_LONG: return Component::LONG;
    case VTK_UNSIGNED_LONG_LONG: return Component::ULONGLONG;
    case VTK_LONG_LONG:
    case VTK_ID_TYPE: return sizeof(vtkIdType) == 8 ? Component::LONGLONG : Component::INT;
    case VTK_FLOAT: return Component::FLOAT;
    case VTK_DOUBLE: return Component::DOUBLE;
    default: ok = false; return Component::UNKNOWNCOMPONENTTYPE;
  }
}

/// Bytes a NIfTI-1 or NIfTI-2 file @p path must hold (its vox_offset plus its voxels, from
/// its own header), against the bytes it holds (decompressed for a .nii.gz). NIfTI's library
/// fills voxels missing at the end of a file with zeros and reads on: a truncated file is
/// refused here instead.
void check_nifti_complete(const std::string& path, bool compressed)
{
  znzFile f = znzopen(path.c_str(), "rb", compressed ? 1 : 0);
  if (znz_isnull(f))
    throw Error(ErrorCode::Io, "cannot read '" + path + "': cannot open the file");
  unsigned char header[540] = {};
  std::uint64_t held = znzread(header, 1, sizeof header, f);
  auto get = [&](auto value, std::size_t offset, bool swap) {
    std::memcpy(&value, header + offset, sizeof value);
    if (swap)
    {
      unsigned char* b = reinterpret_cast<unsigned char*>(&value);
      std::reverse(b, b + sizeof value);
    }
    return value;
  };
  const std::int32_t size_le = get(std::int32_t{}, 0, false);
  const std::int32_t size_be = get(std::int32_t{}, 0, true);
  const bool nifti2 = size_le == 540 || size_be == 540;
  const bool swap = nifti2 ? size_le != 540 : size_le != 348;
  if (!nifti2 && size_le != 348 && size_be != 348)
  {
    znzclose(f);
    return; // not a header we know: ITK has read it, leave it at that
  }
  std::uint64_t needed = 0;
  if (nifti2)
  {
    std::uint64_t voxels = 1;
    const std::int64_t rank = get(std::int64_t{}, 16, swap);
    for (std::int64_t d = 1; d <= std::min<std::int64_t>(rank, 7); ++d)
      voxels *= static_cast<std::uint64_t>(std::max<std::int64_t>(1, get(std::int64_t{}, 16 + 8 * d, swap)));
    needed = static_cast<std::uint64_t>(get(std::int64_t{}, 168, swap)) +
      voxels * static_cast<std::uint64_t>(std::max<std::int16_t>(0, get(std::int16_t{}, 14, swap))) / 8;
  }
  else
  {
    std::uint64_t voxels = 1;
    const std::int16_t rank = get(std::int16_t{}, 40, swap);
    for (int d = 1; d <= std::min<int>(rank, 7); ++d)
      voxels *= static_cast<std::uint64_t>(std::max<std::int16_t>(1, get(std::int16_t{}, 40 + 2 * d, swap)));
    needed = static_cast<std::uint64_t>(std::max(0.0f, get(float{}, 108, swap))) +
      voxels * static_cast<std::uint64_t>(std::max<std::int16_t>(0, get(std::int16_t{}, 72, swap))) / 8;
  }
  if (compressed)
  {
    std::vector<char> chunk(1 << 20);
    for (std::size_t got; held < needed && (got = znzread(chunk.data(), 1, chunk.size(), f)) > 0;)
      held += got;
  }
  else
  {
    struct stat st;
    if (stat(path.c_str(), &st) == 0)
      held = static_cast<std::uint64_t>(st.st_size);
  }
  znzclose(f);
  if (held < needed)
    throw Error(ErrorCode::Io,
      "cannot read '" + path + "': the file is truncated (" + std::to_string(held) +
        " bytes" + (compressed ? " decompressed" : "") + " of the " + std::to_string(needed) +
        " its header announces)");
}

/// Takes what ITK's file layers print to std::cerr (MetaIO reports a short data block there and
/// returns as if it had read it) while it lives.
class CaptureStandardError
{
public:
  CaptureStandardError() : previous_(std::cerr.rdbuf(text_.rdbuf())) {}
  ~CaptureStandardError() { std::cerr.rdbuf(previous_); }
  std::string Text() const { return text_.str(); }
  CaptureStandardError(const CaptureStandardError&) = delete;
  void operator=(const CaptureStandardError&) = delete;

private:
  std::ostringstream text_;
  std::streambuf* previous_;
};

std::string describe_itk_exception(const std::exception& e)
{
  std::string text = e.what();
  if (auto* ie = dynamic_cast<const itk::ExceptionObject*>(&e))
    text = ie->GetDescription();
  // "ITK ERROR: NrrdImageIO(0x55d0c8a0): Read: ..." -> "Read: ..."
  if (text.rfind("ITK ERROR: ", 0) == 0)
  {
    const auto colon = text.find("): ");
    if (colon != std::string::npos)
      text = text.substr(colon + 3);
  }
  return text;
}

std::string folder_of(const std::string& path)
{
  const auto slash = path.find_last_of('/');
  if (slash == std::string::npos)
    return ".";
  return slash == 0 ? "/" : path.substr(0, slash);
}

std::string file_name_of(const std::string& path)
{
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

/// Removes @p dir and the files in it (one level: the temporary folder of a write).
void remove_folder(const std::string& dir)
{
  if (DIR* d = opendir(dir.c_str()))
  {
    while (dirent* entry = readdir(d))
    {
      const std::string name = entry->d_name;
      if (name != "." && name != "..")
        std::remove((dir + "/" + name).c_str());
    }
    closedir(d);
  }
  rmdir(dir.c_str());
}

std::vector<std::string> files_in(const std::string& dir)
{
  std::vector<std::string> names;
  if (DIR* d = opendir(dir.c_str()))
  {
    while (dirent* entry = readdir(d))
    {
      const std::string name = entry->d_name;
      if (name != "." && name != "..")
        names.push_back(name);
    }
    closedir(d);
  }
  return names;
}
} // namespace

std::string vtkBaryImageIO::Extension(const std::string& path)
{
  const std::string name = file_name_of(path);
  std::string lower(name);
  std::transform(lower.begin(), lower.end(), lower.begin(),
    [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  const std::string gz = ".nii.gz";
  if (lower.size() > gz.size() && lower.compare(lower.size() - gz.size(), gz.size(), gz) == 0)
    return gz;
  const auto dot = lower.find_last_of('.');
  if (dot == std::string::npos || dot == 0)
    return "";
  return lower.substr(dot);
}

bool vtkBaryImageIO::CanRead(const std::string& path)
{
  const std::string ext = Extension(path);
  return ext == ".nii" || ext == ".nii.gz" || ext == ".nrrd" || ext == ".nhdr" ||
    ext == ".mha" || ext == ".mhd";
}

bool vtkBaryImageIO::CanWrite(const std::string& path)
{
  const std::string ext = Extension(path);
  return ext == ".nii" || ext == ".nii.gz" || ext == ".nrrd" || ext == ".mha" || ext == ".mhd";
}

vtkSmartPointer<vtkImageData> vtkBaryImageIO::Read(const std::string& path)
{
  const std::string ext = Extension(path);
  struct stat st;
  if (stat(path.c_str(), &st) != 0)
    throw Error(ErrorCode::Io, "cannot read '" + path + "': no such file");
  if (!S_ISREG(st.st_mode))
    throw Error(ErrorCode::Io, "cannot read '" + path + "': not a regular file");
  if (access(path.c_str(), R_OK) != 0)
    throw Error(ErrorCode::Io, "cannot read '" + path + "': permission denied");
  itk::ImageIOBase::Pointer io = image_io_for(ext);
  if (!io)
    throw Error(ErrorCode::Io,
      "cannot read '" + path + "': unknown image file extension '" + ext +
        "' (readable: .nii, .nii.gz, .nrrd, .nhdr, .mha, .mhd)");
  const char* format = ext == ".nii" || ext == ".nii.gz" ? "NIfTI"
    : ext == ".nrrd" || ext == ".nhdr"                   ? "NRRD"
                                                         : "MetaImage";

  auto image = vtkSmartPointer<vtkImageData>::New();
  try
  {
    if (!io->CanReadFile(path.c_str()))
      throw Error(ErrorCode::Io,
        "cannot read '" + path + "': not a " + format + " image ITK can read (" +
          (st.st_size == 0 ? "the file is empty" : "malformed or truncated header") + ")");
    io->SetFileName(path);
    io->ReadImageInformation();

    const unsigned ndim = io->GetNumberOfDimensions();
    if (ndim < 1)
      throw Error(ErrorCode::Io, "cannot read '" + path + "': the image has no dimensions");
    for (unsigned d = 3; d < ndim; ++d)
      if (io->GetDimensions(d) != 1 && d == 4 && std::string(format) == "NIfTI")
        throw Error(ErrorCode::Io,
          "cannot read '" + path + "': " + std::to_string(io->GetDimensions(d)) +
            " values per voxel along NIfTI's 5th axis that ITK 5.2 does not take as vector "
            "components: its intent is not NIFTI_INTENT_VECTOR (1007) - ITK 5.2 reads e.g. "
            "displacement vectors (intent 1006) as a 5-D scalar image; write the field as NRRD "
            "or MetaImage, or as NIfTI with intent 1007");
      else if (io->GetDimensions(d) != 1)
        throw Error(ErrorCode::Io,
          "cannot read '" + path + "': a " + std::to_string(ndim) + "-D image (axis " +
            std::to_string(d + 1) + " has " + std::to_string(io->GetDimensions(d)) +
            " samples); only 2-D and 3-D images are supported (extract one volume first)");
    const int vtk_type = vtk_type_of(io->GetComponentType());
    if (vtk_type < 0)
      throw Error(ErrorCode::Io,
        "cannot read '" + path + "': unsupported voxel component type " +
          itk::ImageIOBase::GetComponentTypeAsString(io->GetComponentType()));
    const unsigned components = io->GetNumberOfComponents();
    if (components < 1)
      throw Error(ErrorCode::Io, "cannot read '" + path + "': voxels without components");

    int dims[3] = { 1, 1, 1 };
    double spacing[3] = { 1, 1, 1 };
    double origin[3] = { 0, 0, 0 };
    vtkNew<vtkMatrix3x3> direction; // identity
    const unsigned used = std::min(ndim, 3u);
    for (unsigned d = 0; d < used; ++d)
    {
      const itk::SizeValueType n = io->GetDimensions(d);
      if (n < 1 || n > static_cast<itk::SizeValueType>(VTK_INT_MAX))
        throw Error(ErrorCode::Io,
          "cannot read '" + path + "': axis " + std::to_string(d + 1) + " has " +
            std::to_string(n) + " samples");
      dims[d] = static_cast<int>(n);
      spacing[d] = io->GetSpacing(d);
      origin[d] = io->GetOrigin(d);
      const std::vector<double> axis = io->GetDirection(d);
      for (unsigned r = 0; r < used && r < axis.size(); ++r)
        direction->SetElement(static_cast<int>(r), static_cast<int>(d), axis[r]);
    }
    for (int d = 0; d < 3; ++d)
    {
      if (!std::isfinite(spacing[d]) || !std::isfinite(origin[d]))
        throw Error(ErrorCode::Io,
          "cannot read '" + path + "': non-finite spacing or origin on axis " +
            std::to_string(d + 1));
      for (int r = 0; r < 3; ++r)
        if (!std::isfinite(direction->GetElement(r, d)))
          throw Error(ErrorCode::Io,
            "cannot read '" + path + "': non-finite direction matrix");
    }

    const vtkIdType voxels = static_cast<vtkIdType>(dims[0]) * dims[1] * dims[2];
    vtkSmartPointer<vtkDataArray> values;
    values.TakeReference(vtkDataArray::CreateDataArray(vtk_type));
    values->SetName("ImageScalars");
    values->SetNumberOfComponents(static_cast<int>(components));
    values->SetNumberOfTuples(voxels);
    const auto expected = static_cast<itk::ImageIOBase::SizeType>(voxels) * components *
      values->GetDataTypeSize();
    if (io->GetImageSizeInBytes() != expected)
      throw Error(ErrorCode::Internal,
        "reading '" + path + "': ITK's buffer size does not match the image's extent");

    itk::ImageIORegion region(ndim);
    for (unsigned d = 0; d < ndim; ++d)
    {
      region.SetIndex(d, 0);
      region.SetSize(d, io->GetDimensions(d));
    }
    io->SetIORegion(region);
    std::string messages;
    {
      CaptureStandardError capture;
      io->Read(values->GetVoidPointer(0));
      messages = capture.Text();
    }
    // MetaIO parses the header again while reading: only its reports of failure count (a
    // short data block, a failed decompression), not remarks on a header ITK accepted.
    for (const char* failure : { "read completely", "ailed", "rror", "annot" })
      if (messages.find(failure) != std::string::npos)
        throw Error(ErrorCode::Io, "cannot read '" + path + "': " + messages);
    if (ext == ".nii" || ext == ".nii.gz")
      check_nifti_complete(path, ext == ".nii.gz");

    image->SetDimensions(dims);
    image->SetSpacing(spacing);
    image->SetOrigin(origin);
    image->SetDirectionMatrix(direction);
    image->GetPointData()->SetScalars(values);
  }
  catch (const Error&)
  {
    throw;
  }
  catch (const std::exception& e)
  {
    throw Error(ErrorCode::Io, "cannot read '" + path + "': " + describe_itk_exception(e));
  }
  return image;
}

void vtkBaryImageIO::Write(vtkImageData* image, const std::string& path)
{
  if (!image)
    throw Error(ErrorCode::InvalidArgument, "nothing to write to '" + path + "'");
  const std::string ext = Extension(path);
  if (!CanWrite(path))
    throw Error(ErrorCode::Io,
      "cannot write '" + path + "': unknown image file extension '" + ext +
        "' (writable: .nii, .nii.gz, .nrrd, .mha, .mhd)");
  vtkDataArray* values = image->GetPointData()->GetScalars();
  if (!values)
    throw Error(ErrorCode::InvalidArgument,
      "cannot write '" + path + "': the image has no point scalars");
  const int components = values->GetNumberOfComponents();
  if (components != 1 && components != 3)
    throw Error(ErrorCode::InvalidArgument,
      "cannot write '" + path + "': voxels of " + std::to_string(components) +
        " components (scalar images and 3-component vector images only)");
  bool known = false;
  const Component type = itk_type_of(values->GetDataType(), known);
  if (!known)
    throw Error(ErrorCode::InvalidArgument,
      "cannot write '" + path + "': voxel type " + values->GetDataTypeAsString() +
        " has no counterpart in the image formats");
  int extent[6];
  image->GetExtent(extent);
  const int dims[3] = { extent[1] - extent[0] + 1, extent[3] - extent[2] + 1,
    extent[5] - extent[4] + 1 };
  if (dims[0] < 1 || dims[1] < 1 || dims[2] < 1)
    throw Error(ErrorCode::InvalidArgument, "cannot write '" + path + "': the image is empty");
  if (values->GetNumberOfTuples() != static_cast<vtkIdType>(dims[0]) * dims[1] * dims[2])
    throw Error(ErrorCode::InvalidArgument,
      "cannot write '" + path + "': the scalars have " +
        std::to_string(values->GetNumberOfTuples()) + " values for " +
        std::to_string(static_cast<vtkIdType>(dims[0]) * dims[1] * dims[2]) + " voxels");

  const double* image_spacing = image->GetSpacing();
  vtkMatrix3x3* direction = image->GetDirectionMatrix();
  double D[3][3];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
    {
      D[r][c] = direction->GetElement(r, c);
      if (!std::isfinite(D[r][c]))
        throw Error(ErrorCode::InvalidArgument,
          "cannot write '" + path + "': the direction matrix is not finite");
    }
  for (int d = 0; d < 3; ++d)
    if (!std::isfinite(image_spacing[d]) || image_spacing[d] <= 0)
      throw Error(ErrorCode::InvalidArgument,
        "cannot write '" + path + "': spacing " + std::to_string(image_spacing[d]) +
          " on axis " + std::to_string(d + 1) + " (must be positive and finite)");
  const double det = vtkMath::Determinant3x3(D);
  double norm[3];
  for (int c = 0; c < 3; ++c)
    norm[c] = std::sqrt(D[0][c] * D[0][c] + D[1][c] * D[1][c] + D[2][c] * D[2][c]);
  if (!(std::abs(det) > 1e-12 * norm[0] * norm[1] * norm[2]) || !(norm[0] * norm[1] * norm[2] > 0))
    throw Error(ErrorCode::InvalidArgument,
      "cannot write '" + path + "': the direction matrix is singular (determinant " +
        std::to_string(det) + ")");
  // The physical position of the first voxel (extent minimum), the files' origin.
  double origin[3];
  const double first[3] = { extent[0] * image_spacing[0], extent[2] * image_spacing[1],
    extent[4] * image_spacing[2] };
  for (int r = 0; r < 3; ++r)
  {
    origin[r] = image->GetOrigin()[r] + D[r][0] * first[0] + D[r][1] * first[1] +
      D[r][2] * first[2];
    if (!std::isfinite(origin[r]))
      throw Error(ErrorCode::InvalidArgument,
        "cannot write '" + path + "': the origin is not finite");
  }
  // The files hold unit direction columns (ITK's convention; NRRD stores direction · spacing
  // and ITK splits it so on reading): a column of another length goes into the spacing, which
  // leaves every voxel's physical point unchanged.
  double spacing[3];
  for (int c = 0; c < 3; ++c)
  {
    spacing[c] = image_spacing[c] * norm[c];
    for (int r = 0; r < 3; ++r)
      D[r][c] /= norm[c];
  }

  // A temporary folder beside the target (same file system: the renames are atomic), holding
  // the file under its final name (a .mhd names its data file after itself).
  const std::string folder = folder_of(path);
  const std::string name = file_name_of(path);
  struct stat st;
  if (stat(folder.c_str(), &st) != 0 || !S_ISDIR(st.st_mode))
    throw Error(ErrorCode::Io, "cannot write '" + path + "': no such folder '" + folder + "'");
  std::string pattern = folder + "/." + name + ".tmpXXXXXX";
  std::vector<char> buffer(pattern.begin(), pattern.end());
  buffer.push_back('\0');
  if (!mkdtemp(buffer.data()))
    throw Error(ErrorCode::Io,
      "cannot write '" + path + "': cannot create a file in '" + folder + "' (" +
        std::strerror(errno) + ")");
  const std::string tmp_dir(buffer.data());
  const std::string tmp = tmp_dir + "/" + name;

  try
  {
    itk::ImageIOBase::Pointer io = image_io_for(ext);
    io->SetNumberOfDimensions(3);
    for (unsigned d = 0; d < 3; ++d)
    {
      io->SetDimensions(d, static_cast<itk::SizeValueType>(dims[d]));
      io->SetSpacing(d, spacing[d]);
      io->SetOrigin(d, origin[d]);
      io->SetDirection(d, std::vector<double>{ D[0][d], D[1][d], D[2][d] });
    }
    io->SetComponentType(type);
    io->SetNumberOfComponents(static_cast<unsigned>(components));
    io->SetPixelType(components == 3 ? PixelKind::VECTOR : PixelKind::SCALAR);
    io->SetUseCompression(ext != ".nii");
    // zlib's fastest level where the format's IO honours it (MetaImage, NRRD; ITK 5.2's NIfTI
    // IO keeps its own): a displacement field's doubles barely compress (their mantissas), label
    // maps still shrink by their runs of equal values
    io->SetCompressionLevel(1);
    io->SetFileName(tmp);
    itk::ImageIORegion region(3);
    for (unsigned d = 0; d < 3; ++d)
    {
      region.SetIndex(d, 0);
      region.SetSize(d, static_cast<itk::SizeValueType>(dims[d]));
    }
    io->SetIORegion(region);
    io->Write(values->GetVoidPointer(0));
  }
  catch (const std::exception& e)
  {
    remove_folder(tmp_dir);
    throw Error(ErrorCode::Io, "cannot write '" + path + "': " + describe_itk_exception(e));
  }

  // Into place: the data files first (a .mhd's .raw / .zraw), the named file last, so that the
  // file the user asked for appears only when everything it refers to is there.
  std::vector<std::string> written = files_in(tmp_dir);
  std::stable_partition(
    written.begin(), written.end(), [&](const std::string& f) { return f != name; });
  if (std::find(written.begin(), written.end(), name) == written.end())
  {
    remove_folder(tmp_dir);
    throw Error(ErrorCode::Io, "cannot write '" + path + "': ITK wrote no file");
  }
  for (const std::string& f : written)
    if (std::rename((tmp_dir + "/" + f).c_str(), (folder + "/" + f).c_str()) != 0)
    {
      const std::string why = std::strerror(errno);
      remove_folder(tmp_dir);
      throw Error(ErrorCode::Io,
        "cannot write '" + path + "': moving the temporary file into place failed (" + why +
          ")");
    }
  rmdir(tmp_dir.c_str());
}
