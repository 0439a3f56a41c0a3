// Tests of vtkBaryImageIO (BaryLab::BaryLabMedical): NIfTI, NRRD and MetaImage written and read
// through ITK. Geometry (origin, anisotropic spacing, a non-identity direction) and voxel values
// survive a round trip in each format; independently of ITK, the files' own headers are parsed
// here to check the conventions: NIfTI's sform is RAS (LPS with x and y negated), NRRD's space
// is left-posterior-superior with "space directions" = direction · spacing, and vector images
// carry the vector layout ITK's displacement fields use (NIfTI intent 1007, 5-D; NRRD kinds
// vector). Bad files and bad writes throw bary::Error naming the file and leave no file behind.
#include "vtkBaryImageIO.h"

#include "core/common/error.h"

#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkMatrix3x3.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkShortArray.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace
{
namespace fs = std::filesystem;
using Matrix3 = std::array<std::array<double, 3>, 3>;

/// A fresh, empty folder @p name under BARYLAB_TEST_OUTPUT_DIR, of the running test's own.
fs::path Scratch(const std::string& name)
{
  const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string owner = std::string(test->test_suite_name()) + "." + test->name();
  std::replace(owner.begin(), owner.end(), '/', '_');
  const fs::path dir = fs::path(BARYLAB_TEST_OUTPUT_DIR) / "filters_image_io" / owner / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::set<std::string> ListFolder(const fs::path& dir)
{
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir))
    names.insert(entry.path().filename().string());
  return names;
}

/// A rotation by @p angle about the unit axis along @p axis (Rodrigues), a proper orthonormal
/// direction matrix with no zero entries for a generic axis.
Matrix3 Rotation(std::array<double, 3> axis, double angle)
{
  const double n = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
  for (double& a : axis)
    a /= n;
  const double c = std::cos(angle), s = std::sin(angle), t = 1 - c;
  const double x = axis[0], y = axis[1], z = axis[2];
  return { { { t * x * x + c, t * x * y - s * z, t * x * z + s * y },
    { t * x * y + s * z, t * y * y + c, t * y * z - s * x },
    { t * x * z - s * y, t * y * z + s * x, t * z * z + c } } };
}

const Matrix3 kDirection = Rotation({ 1.0, 2.0, 3.0 }, 0.5);
const std::array<double, 3> kSpacing = { 0.7, 1.3, 2.5 };
const std::array<double, 3> kOrigin = { -12.5, 30.25, 7.0 };
const std::array<int, 3> kDims = { 7, 5, 4 };

vtkSmartPointer<vtkImageData> EmptyImage(const Matrix3& direction = kDirection)
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(kDims.data());
  image->SetSpacing(kSpacing.data());
  image->SetOrigin(kOrigin.data());
  vtkNew<vtkMatrix3x3> m;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      m->SetElement(r, c, direction[r][c]);
  image->SetDirectionMatrix(m);
  return image;
}

/// Voxel values that differ between neighbours along each axis (an axis swap or flip shows).
double Pattern(int i, int j, int k, int component = 0)
{
  return (i * 7 + j * 3 + k * 11 + component * 5) % 23 - 9;
}

/// A label map of signed shorts (values -9 .. 13).
vtkSmartPointer<vtkImageData> ShortImage(const Matrix3& direction = kDirection)
{
  auto image = EmptyImage(direction);
  vtkNew<vtkShortArray> values;
  values->SetNumberOfTuples(image->GetNumberOfPoints());
  for (int k = 0; k < kDims[2]; ++k)
    for (int j = 0; j < kDims[1]; ++j)
      for (int i = 0; i < kDims[0]; ++i)
        values->SetValue(i + kDims[0] * (j + kDims[1] * k), static_cast<short>(Pattern(i, j, k)));
  image->GetPointData()->SetScalars(values);
  return image;
}

/// A 3-component double image (a displacement field), values with all their digits.
vtkSmartPointer<vtkImageData> VectorImage()
{
  auto image = EmptyImage();
  vtkNew<vtkDoubleArray> values;
  values->SetNumberOfComponents(3);
  values->SetNumberOfTuples(image->GetNumberOfPoints());
  for (int k = 0; k < kDims[2]; ++k)
    for (int j = 0; j < kDims[1]; ++j)
      for (int i = 0; i < kDims[0]; ++i)
        for (int c = 0; c < 3; ++c)
          values->SetComponent(i + kDims[0] * (j + kDims[1] * k), c,
            Pattern(i, j, k, c) / 3.0 + std::sqrt(2.0) * c);
  image->GetPointData()->SetScalars(values);
  return image;
}

/// Geometry equal within @p tol (relative to the quantity's size, at least 1).
void ExpectSameGeometry(vtkImageData* expected, vtkImageData* actual, double tol)
{
  int de[3], da[3];
  expected->GetDimensions(de);
  actual->GetDimensions(da);
  for (int d = 0; d < 3; ++d)
  {
    EXPECT_EQ(de[d], da[d]) << "axis " << d;
    EXPECT_NEAR(expected->GetSpacing()[d], actual->GetSpacing()[d], tol) << "spacing " << d;
    EXPECT_NEAR(expected->GetOrigin()[d], actual->GetOrigin()[d],
      tol * std::max(1.0, std::abs(expected->GetOrigin()[d])))
      << "origin " << d;
    for (int r = 0; r < 3; ++r)
      EXPECT_NEAR(expected->GetDirectionMatrix()->GetElement(r, d),
        actual->GetDirectionMatrix()->GetElement(r, d), tol)
        << "direction (" << r << ", " << d << ")";
  }
}

/// Same type, components and every value exactly.
void ExpectSameValues(vtkImageData* expected, vtkImageData* actual)
{
  vtkDataArray* a = expected->GetPointData()->GetScalars();
  vtkDataArray* b = actual->GetPointData()->GetScalars();
  ASSERT_NE(b, nullptr);
  EXPECT_EQ(a->GetDataType(), b->GetDataType())
    << a->GetDataTypeAsString() << " vs " << b->GetDataTypeAsString();
  ASSERT_EQ(a->GetNumberOfComponents(), b->GetNumberOfComponents());
  ASSERT_EQ(a->GetNumberOfTuples(), b->GetNumberOfTuples());
  int mismatches = 0;
  for (vtkIdType t = 0; t < a->GetNumberOfTuples(); ++t)
    for (int c = 0; c < a->GetNumberOfComponents(); ++c)
      if (a->GetComponent(t, c) != b->GetComponent(t, c) && ++mismatches < 5)
        ADD_FAILURE() << "voxel " << t << " component " << c << ": " << a->GetComponent(t, c)
                      << " written, " << b->GetComponent(t, c) << " read";
  EXPECT_EQ(mismatches, 0);
}

/// The physical (LPS) point of index (i, j, k) computed here from the constants.
std::array<double, 3> PhysicalPoint(const Matrix3& D, int i, int j, int k)
{
  const double p[3] = { i * kSpacing[0], j * kSpacing[1], k * kSpacing[2] };
  std::array<double, 3> x{};
  for (int r = 0; r < 3; ++r)
    x[r] = kOrigin[r] + D[r][0] * p[0] + D[r][1] * p[1] + D[r][2] * p[2];
  return x;
}

std::string ReadBytes(const fs::path& path)
{
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

template<class T>
T At(const std::string& bytes, std::size_t offset)
{
  T value;
  std::memcpy(&value, bytes.data() + offset, sizeof(T));
  return value;
}

/// The value after "@p key:" on its line of a NRRD header.
std::string NrrdField(const std::string& header, const std::string& key)
{
  std::istringstream in(header);
  std::string line;
  while (std::getline(in, line) && !line.empty())
    if (line.rfind(key + ":", 0) == 0)
      return line.substr(key.size() + 1);
  return "";
}

/// The numbers of a NRRD vector list "(a,b,c) (d,e,f) ...".
std::vector<double> NrrdNumbers(std::string text)
{
  for (char& ch : text)
    if (ch == '(' || ch == ')' || ch == ',')
      ch = ' ';
  std::istringstream in(text);
  std::vector<double> numbers;
  double x;
  while (in >> x)
    numbers.push_back(x);
  return numbers;
}

void ExpectThrows(const std::function<void()>& call, bary::ErrorCode code,
  const std::string& path, const std::string& needle = "")
{
  try
  {
    call();
    ADD_FAILURE() << "no error for '" << path << "'";
  }
  catch (const bary::Error& e)
  {
    EXPECT_EQ(e.code(), code) << bary::to_string(e.code()) << ": " << e.what();
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos)
      << "the message should name the file: " << e.what();
    if (!needle.empty())
    {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos)
        << "expected '" << needle << "' in: " << e.what();
    }
  }
}

// NIfTI stores its geometry as float32 (pixdim, quatern_*, qoffset_*, srow_*): 1e-5 relative.
// NRRD and MetaImage store decimal text that ITK writes with enough digits: 1e-9.
double GeometryTolerance(const std::string& ext)
{
  return ext == ".nii" || ext == ".nii.gz" ? 1e-5 : 1e-9;
}

class ImageIOFormat : public ::testing::TestWithParam<std::string>
{
};

TEST_P(ImageIOFormat, LabelMapRoundTripKeepsGeometryAndValues)
{
  const std::string ext = GetParam();
  const fs::path dir = Scratch("out");
  const std::string path = (dir / ("label" + ext)).string();
  auto written = ShortImage();
  vtkBaryImageIO::Write(written, path);
  auto read = vtkBaryImageIO::Read(path);
  ExpectSameGeometry(written, read, GeometryTolerance(ext));
  ExpectSameValues(written, read);
  // The corner voxel's physical point, by hand from the constants, against vtkImageData's.
  double x[3];
  read->TransformIndexToPhysicalPoint(kDims[0] - 1, kDims[1] - 1, kDims[2] - 1, x);
  const auto expected = PhysicalPoint(kDirection, kDims[0] - 1, kDims[1] - 1, kDims[2] - 1);
  for (int d = 0; d < 3; ++d)
    EXPECT_NEAR(x[d], expected[d], 1e-4) << d;
  // Only the files of the format, no temporary left.
  std::set<std::string> expected_files = { "label" + ext };
  if (ext == ".mhd")
    expected_files.insert("label.zraw");
  EXPECT_EQ(ListFolder(dir), expected_files);
}

TEST_P(ImageIOFormat, FloatAndUnsignedCharKeepTheirType)
{
  const std::string ext = GetParam();
  const fs::path dir = Scratch("out");
  auto image = EmptyImage();
  vtkNew<vtkFloatArray> f;
  f->SetNumberOfTuples(image->GetNumberOfPoints());
  for (vtkIdType t = 0; t < f->GetNumberOfTuples(); ++t)
    f->SetValue(t, static_cast<float>(std::sin(0.37 * t) * 1000.0));
  image->GetPointData()->SetScalars(f);
  vtkBaryImageIO::Write(image, (dir / ("f" + ext)).string());
  auto read = vtkBaryImageIO::Read((dir / ("f" + ext)).string());
  ExpectSameValues(image, read);

  vtkNew<vtkUnsignedCharArray> u;
  u->SetNumberOfTuples(image->GetNumberOfPoints());
  for (vtkIdType t = 0; t < u->GetNumberOfTuples(); ++t)
    u->SetValue(t, static_cast<unsigned char>((t * 37) % 256));
  image->GetPointData()->SetScalars(u);
  vtkBaryImageIO::Write(image, (dir / ("u" + ext)).string());
  read = vtkBaryImageIO::Read((dir / ("u" + ext)).string());
  ExpectSameValues(image, read);
}

TEST_P(ImageIOFormat, VectorImageRoundTrip)
{
  const std::string ext = GetParam();
  const fs::path dir = Scratch("out");
  const std::string path = (dir / ("field" + ext)).string();
  auto written = VectorImage();
  vtkBaryImageIO::Write(written, path);
  auto read = vtkBaryImageIO::Read(path);
  ExpectSameGeometry(written, read, GeometryTolerance(ext));
  ExpectSameValues(written, read);
}

INSTANTIATE_TEST_SUITE_P(Formats, ImageIOFormat,
  ::testing::Values(".nii", ".nii.gz", ".nrrd", ".mha", ".mhd"),
  [](const ::testing::TestParamInfo<std::string>& format) {
    std::string name = format.param.substr(1);
    std::replace(name.begin(), name.end(), '.', '_');
    return name;
  });

// The NIfTI header, parsed here (nifti1.h's layout): the sform maps (i, j, k, 1) to RAS, which
// must be LPS's x and y negated; a vector image has the 5-D vector layout and intent.
TEST(ImageIO, NiftiHeaderIsRasAndVectorLayout)
{
  const fs::path dir = Scratch("out");
  vtkBaryImageIO::Write(ShortImage(), (dir / "label.nii").string());
  const std::string bytes = ReadBytes(dir / "label.nii");
  ASSERT_GE(bytes.size(), 352u);
  EXPECT_EQ(At<int32_t>(bytes, 0), 348);
  EXPECT_EQ(bytes.substr(344, 3), std::string("n+1"));
  EXPECT_EQ(At<int16_t>(bytes, 40), 3);  // dim[0]
  EXPECT_EQ(At<int16_t>(bytes, 42), kDims[0]);
  EXPECT_EQ(At<int16_t>(bytes, 44), kDims[1]);
  EXPECT_EQ(At<int16_t>(bytes, 46), kDims[2]);
  EXPECT_EQ(At<int16_t>(bytes, 70), 4);  // datatype DT_INT16
  ASSERT_GT(At<int16_t>(bytes, 254), 0); // sform_code
  for (int r = 0; r < 3; ++r)
  {
    const double sign = r < 2 ? -1.0 : 1.0; // LPS -> RAS
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(At<float>(bytes, 280 + 16 * r + 4 * c), sign * kDirection[r][c] * kSpacing[c],
        1e-6)
        << "srow " << r << ", " << c;
    EXPECT_NEAR(At<float>(bytes, 280 + 16 * r + 12), sign * kOrigin[r], 1e-5) << "srow " << r;
  }

  vtkBaryImageIO::Write(VectorImage(), (dir / "field.nii").string());
  const std::string field = ReadBytes(dir / "field.nii");
  ASSERT_GE(field.size(), 352u);
  EXPECT_EQ(At<int16_t>(field, 40), 5); // dim[0]: x y z t vector
  EXPECT_EQ(At<int16_t>(field, 48), 1); // dim[4]: one time point
  EXPECT_EQ(At<int16_t>(field, 50), 3); // dim[5]: three components
  EXPECT_EQ(At<int16_t>(field, 68), 1007); // NIFTI_INTENT_VECTOR
  EXPECT_EQ(At<int16_t>(field, 70), 64);   // DT_FLOAT64

  // The same file with intent NIFTI_INTENT_DISPVECT (1006), as other tools write displacement
  // fields: ITK 5.2 reads it as a 5-D scalar image, which is refused with the reason.
  std::string dispvect = field;
  const int16_t code = 1006;
  std::memcpy(&dispvect[68], &code, sizeof code);
  const std::string dispvect_path = (dir / "dispvect.nii").string();
  std::ofstream(dispvect_path, std::ios::binary) << dispvect;
  ExpectThrows([&] { vtkBaryImageIO::Read(dispvect_path); }, bary::ErrorCode::Io, dispvect_path,
    "1007");
}

// The NRRD header, parsed here: LPS space, origin and "space directions" (the columns of
// direction · spacing), and the vector kind of a displacement field.
TEST(ImageIO, NrrdHeaderIsLpsAndVectorKind)
{
  const fs::path dir = Scratch("out");
  vtkBaryImageIO::Write(ShortImage(), (dir / "label.nrrd").string());
  const std::string header = ReadBytes(dir / "label.nrrd");
  EXPECT_NE(NrrdField(header, "space").find("left-posterior-superior"), std::string::npos)
    << header;
  const auto origin = NrrdNumbers(NrrdField(header, "space origin"));
  ASSERT_EQ(origin.size(), 3u) << header;
  const auto directions = NrrdNumbers(NrrdField(header, "space directions"));
  ASSERT_EQ(directions.size(), 9u) << header;
  for (int c = 0; c < 3; ++c)
  {
    EXPECT_NEAR(origin[c], kOrigin[c], 1e-9);
    for (int r = 0; r < 3; ++r)
      EXPECT_NEAR(directions[3 * c + r], kDirection[r][c] * kSpacing[c], 1e-9);
  }

  vtkBaryImageIO::Write(VectorImage(), (dir / "field.nrrd").string());
  const std::string field = ReadBytes(dir / "field.nrrd");
  EXPECT_NE(NrrdField(field, "kinds").find("vector domain domain domain"), std::string::npos)
    << NrrdField(field, "kinds");
  EXPECT_NE(NrrdField(field, "type").find("double"), std::string::npos);
}

// A non-orthogonal (sheared) but invertible direction with unit columns survives NRRD and
// MetaImage (NIfTI's qform holds rotations only). A direction column of another length is
// written as a unit column with the length in the spacing: the same physical points.
TEST(ImageIO, NonOrthogonalDirectionInNrrdAndMetaImage)
{
  Matrix3 sheared = kDirection;
  for (int r = 0; r < 3; ++r)
    sheared[r][1] += 0.3 * kDirection[r][0];
  const double n = std::sqrt(sheared[0][1] * sheared[0][1] + sheared[1][1] * sheared[1][1] +
    sheared[2][1] * sheared[2][1]);
  for (int r = 0; r < 3; ++r)
    sheared[r][1] /= n;
  const fs::path dir = Scratch("out");
  for (const std::string ext : { ".nrrd", ".mha" })
  {
    auto written = ShortImage(sheared);
    vtkBaryImageIO::Write(written, (dir / ("s" + ext)).string());
    auto read = vtkBaryImageIO::Read((dir / ("s" + ext)).string());
    ExpectSameGeometry(written, read, 1e-9);
    ExpectSameValues(written, read);
  }

  Matrix3 scaled = kDirection;
  for (int r = 0; r < 3; ++r)
    scaled[r][2] *= 2.0;
  auto read = ShortImage(scaled);
  vtkBaryImageIO::Write(read, (dir / "scaled.nrrd").string());
  read = vtkBaryImageIO::Read((dir / "scaled.nrrd").string());
  EXPECT_NEAR(read->GetSpacing()[2], 2.0 * kSpacing[2], 1e-9);
  for (int r = 0; r < 3; ++r)
    EXPECT_NEAR(read->GetDirectionMatrix()->GetElement(r, 2), kDirection[r][2], 1e-9);
  double x[3];
  read->TransformIndexToPhysicalPoint(3, 2, 1, x);
  const auto expected = PhysicalPoint(scaled, 3, 2, 1);
  for (int d = 0; d < 3; ++d)
    EXPECT_NEAR(x[d], expected[d], 1e-9);
}

// An extent that does not start at 0: the file's origin is the first voxel's physical point.
TEST(ImageIO, ExtentNotFromZeroMovesTheOrigin)
{
  auto image = ShortImage();
  image->SetExtent(2, 2 + kDims[0] - 1, -1, -1 + kDims[1] - 1, 3, 3 + kDims[2] - 1);
  const fs::path dir = Scratch("out");
  vtkBaryImageIO::Write(image, (dir / "e.nrrd").string());
  auto read = vtkBaryImageIO::Read((dir / "e.nrrd").string());
  const auto first = PhysicalPoint(kDirection, 2, -1, 3);
  for (int d = 0; d < 3; ++d)
    EXPECT_NEAR(read->GetOrigin()[d], first[d], 1e-9);
  ExpectSameValues(image, read);
}

// Files written by other programs: the bundled label map (data/generate.py writes its NIfTI
// header with Python's struct, in RAS) read into the LPS geometry data/README.md states, and a
// detached NRRD (.nhdr + raw data) written here by hand, read as its header says.
TEST(ImageIO, ReadsFilesOfOtherWriters)
{
  const std::string organ = std::string(BARYLAB_DATA_DIR) + "/organ_label.nii.gz";
  if (fs::exists(organ))
  {
    auto image = vtkBaryImageIO::Read(organ);
    int dims[3];
    image->GetDimensions(dims);
    EXPECT_EQ(dims[0], 112);
    EXPECT_EQ(dims[1], 96);
    EXPECT_EQ(dims[2], 72);
    const double spacing[3] = { 1.75, 1.75, 2.5 }, origin[3] = { -166.125, -83.375, -205.0 };
    for (int d = 0; d < 3; ++d)
    {
      EXPECT_NEAR(image->GetSpacing()[d], spacing[d], 1e-6);
      EXPECT_NEAR(image->GetOrigin()[d], origin[d], 1e-4);
      for (int r = 0; r < 3; ++r)
        EXPECT_NEAR(image->GetDirectionMatrix()->GetElement(r, d), r == d ? 1.0 : 0.0, 1e-6);
    }
    vtkDataArray* labels = image->GetPointData()->GetScalars();
    EXPECT_EQ(labels->GetDataType(), VTK_UNSIGNED_CHAR);
    vtkIdType organ_voxels = 0, lesion_voxels = 0;
    for (vtkIdType v = 0; v < labels->GetNumberOfTuples(); ++v)
    {
      organ_voxels += labels->GetTuple1(v) != 0;
      lesion_voxels += labels->GetTuple1(v) == 2;
    }
    EXPECT_EQ(organ_voxels, 120538); // data/README.md: organ (1 with 2)
    EXPECT_EQ(lesion_voxels, 712);
  }

  const fs::path dir = Scratch("in");
  {
    std::ofstream header(dir / "hand.nhdr");
    header << "NRRD0004\ntype: short\ndimension: 3\nspace: left-posterior-superior\n"
              "sizes: 4 3 2\nspace directions: (0,2,0) (-1.5,0,0) (0,0,3)\n"
              "kinds: domain domain domain\nendian: little\nencoding: raw\n"
              "space origin: (10,20,30)\ndata file: hand.raw\n";
    std::ofstream raw(dir / "hand.raw", std::ios::binary);
    for (short v = 0; v < 24; ++v)
      raw.write(reinterpret_cast<const char*>(&v), sizeof v);
  }
  auto image = vtkBaryImageIO::Read((dir / "hand.nhdr").string());
  int dims[3];
  image->GetDimensions(dims);
  EXPECT_EQ(dims[0], 4);
  EXPECT_EQ(dims[1], 3);
  EXPECT_EQ(dims[2], 2);
  // axis i along +y with 2 mm, axis j along -x with 1.5 mm, axis k along +z with 3 mm
  const double spacing[3] = { 2.0, 1.5, 3.0 };
  const double D[3][3] = { { 0, -1, 0 }, { 1, 0, 0 }, { 0, 0, 1 } };
  for (int d = 0; d < 3; ++d)
  {
    EXPECT_NEAR(image->GetSpacing()[d], spacing[d], 1e-12);
    EXPECT_NEAR(image->GetOrigin()[d], 10.0 * (d + 1), 1e-12);
    for (int r = 0; r < 3; ++r)
      EXPECT_NEAR(image->GetDirectionMatrix()->GetElement(r, d), D[r][d], 1e-12);
  }
  double x[3];
  image->TransformIndexToPhysicalPoint(3, 2, 1, x); // (10, 20, 30) + 3 (0,2,0) + 2 (-1.5,0,0) + (0,0,3)
  EXPECT_NEAR(x[0], 7.0, 1e-12);
  EXPECT_NEAR(x[1], 26.0, 1e-12);
  EXPECT_NEAR(x[2], 33.0, 1e-12);
  vtkDataArray* values = image->GetPointData()->GetScalars();
  EXPECT_EQ(values->GetDataType(), VTK_SHORT);
  for (vtkIdType v = 0; v < 24; ++v)
    EXPECT_EQ(values->GetTuple1(v), static_cast<double>(v));

  // A 2-D image: one slice, its 2 x 2 direction in the 3 x 3 matrix, the third axis +z.
  {
    std::ofstream header(dir / "flat.nhdr");
    header << "NRRD0004\ntype: unsigned char\ndimension: 2\nspace dimension: 2\nsizes: 3 2\n"
              "space directions: (0,1.5) (-2,0)\nkinds: domain domain\nendian: little\n"
              "encoding: raw\nspace origin: (5,7)\ndata file: flat.raw\n";
    std::ofstream(dir / "flat.raw", std::ios::binary) << "\x01\x02\x03\x04\x05\x06";
  }
  image = vtkBaryImageIO::Read((dir / "flat.nhdr").string());
  image->GetDimensions(dims);
  EXPECT_EQ(dims[0], 3);
  EXPECT_EQ(dims[1], 2);
  EXPECT_EQ(dims[2], 1);
  const double spacing2[3] = { 1.5, 2.0, 1.0 }, origin2[3] = { 5.0, 7.0, 0.0 };
  const double D2[3][3] = { { 0, -1, 0 }, { 1, 0, 0 }, { 0, 0, 1 } };
  for (int d = 0; d < 3; ++d)
  {
    EXPECT_NEAR(image->GetSpacing()[d], spacing2[d], 1e-12);
    EXPECT_NEAR(image->GetOrigin()[d], origin2[d], 1e-12);
    for (int r = 0; r < 3; ++r)
      EXPECT_NEAR(image->GetDirectionMatrix()->GetElement(r, d), D2[r][d], 1e-12);
  }
  values = image->GetPointData()->GetScalars();
  EXPECT_EQ(values->GetDataType(), VTK_UNSIGNED_CHAR);
  for (vtkIdType v = 0; v < 6; ++v)
    EXPECT_EQ(values->GetTuple1(v), static_cast<double>(v + 1));
}

TEST(ImageIO, ExtensionsAndCanReadWrite)
{
  EXPECT_EQ(vtkBaryImageIO::Extension("/a/b.c/Brain.NII.GZ"), ".nii.gz");
  EXPECT_EQ(vtkBaryImageIO::Extension("x.nrrd"), ".nrrd");
  EXPECT_EQ(vtkBaryImageIO::Extension("/a.b/noext"), "");
  EXPECT_TRUE(vtkBaryImageIO::CanRead("a.nhdr"));
  EXPECT_FALSE(vtkBaryImageIO::CanWrite("a.nhdr"));
  for (const char* ext : { ".nii", ".nii.gz", ".nrrd", ".mha", ".mhd" })
    EXPECT_TRUE(vtkBaryImageIO::CanRead(std::string("a") + ext) &&
      vtkBaryImageIO::CanWrite(std::string("a") + ext))
      << ext;
  EXPECT_FALSE(vtkBaryImageIO::CanRead("a.vtp"));
  EXPECT_FALSE(vtkBaryImageIO::CanRead("a.gz"));
}

TEST(ImageIO, BadFilesAreErrorsNamingTheFile)
{
  const fs::path dir = Scratch("in");
  using bary::ErrorCode;
  const std::string missing = (dir / "missing.nii.gz").string();
  ExpectThrows([&] { vtkBaryImageIO::Read(missing); }, ErrorCode::Io, missing, "no such file");
  ExpectThrows([&] { vtkBaryImageIO::Read(dir.string()); }, ErrorCode::Io, dir.string());
  const std::string unknown = (dir / "image.png").string();
  std::ofstream(unknown) << "x";
  ExpectThrows([&] { vtkBaryImageIO::Read(unknown); }, ErrorCode::Io, unknown, "extension");

  // Empty and garbage files in each format.
  for (const std::string ext : { ".nii", ".nii.gz", ".nrrd", ".mha", ".mhd" })
  {
    const std::string empty = (dir / ("empty" + ext)).string();
    std::ofstream(empty).close();
    ExpectThrows([&] { vtkBaryImageIO::Read(empty); }, ErrorCode::Io, empty);
    const std::string garbage = (dir / ("garbage" + ext)).string();
    {
      std::ofstream out(garbage, std::ios::binary);
      for (int i = 0; i < 4096; ++i)
        out.put(static_cast<char>((i * 7919 + 13) % 251));
    }
    ExpectThrows([&] { vtkBaryImageIO::Read(garbage); }, ErrorCode::Io, garbage);
  }

  // Valid headers whose data are cut short.
  const fs::path out = Scratch("out");
  for (const std::string ext : { ".nii", ".nii.gz", ".nrrd", ".mha" })
  {
    const fs::path good = out / ("good" + ext);
    vtkBaryImageIO::Write(ShortImage(), good.string());
    std::string bytes = ReadBytes(good);
    const std::string cut = (dir / ("cut" + ext)).string();
    std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() - 40);
    ExpectThrows([&] { vtkBaryImageIO::Read(cut); }, ErrorCode::Io, cut);
  }
  // A .mhd whose data file is missing.
  vtkBaryImageIO::Write(ShortImage(), (out / "lonely.mhd").string());
  fs::remove(out / "lonely.zraw");
  const std::string lonely = (out / "lonely.mhd").string();
  ExpectThrows([&] { vtkBaryImageIO::Read(lonely); }, ErrorCode::Io, lonely);
}

TEST(ImageIO, BadWritesLeaveNoFile)
{
  using bary::ErrorCode;
  const fs::path dir = Scratch("out");
  const std::string nowhere = (dir / "no_such_folder" / "label.nii.gz").string();
  ExpectThrows([&] { vtkBaryImageIO::Write(ShortImage(), nowhere); }, ErrorCode::Io, nowhere,
    "no such folder");
  EXPECT_FALSE(fs::exists(dir / "no_such_folder"));

  const std::string unknown = (dir / "label.png").string();
  ExpectThrows([&] { vtkBaryImageIO::Write(ShortImage(), unknown); }, ErrorCode::Io, unknown,
    "extension");

  Matrix3 singular = kDirection;
  for (int r = 0; r < 3; ++r)
    singular[r][2] = singular[r][0];
  const std::string flat = (dir / "singular.nrrd").string();
  ExpectThrows([&] { vtkBaryImageIO::Write(ShortImage(singular), flat); },
    ErrorCode::InvalidArgument, flat, "singular");

  auto two = EmptyImage();
  vtkNew<vtkFloatArray> pairs;
  pairs->SetNumberOfComponents(2);
  pairs->SetNumberOfTuples(two->GetNumberOfPoints());
  pairs->FillValue(1.0f);
  two->GetPointData()->SetScalars(pairs);
  const std::string two_path = (dir / "two.mha").string();
  ExpectThrows([&] { vtkBaryImageIO::Write(two, two_path); }, ErrorCode::InvalidArgument,
    two_path, "components");

  auto none = EmptyImage();
  const std::string none_path = (dir / "none.nrrd").string();
  ExpectThrows([&] { vtkBaryImageIO::Write(none, none_path); }, ErrorCode::InvalidArgument,
    none_path, "scalars");

  auto zero = ShortImage();
  zero->SetSpacing(1.0, 0.0, 1.0);
  const std::string zero_path = (dir / "zero.nii").string();
  ExpectThrows([&] { vtkBaryImageIO::Write(zero, zero_path); }, ErrorCode::InvalidArgument,
    zero_path, "spacing");

  EXPECT_TRUE(ListFolder(dir).empty()) << *ListFolder(dir).begin();
}

// Overwriting keeps the old file until the new one is complete; a successful overwrite
// replaces it.
TEST(ImageIO, OverwriteReplacesTheFile)
{
  const fs::path dir = Scratch("out");
  const std::string path = (dir / "label.mha").string();
  vtkBaryImageIO::Write(ShortImage(), path);
  auto image = ShortImage();
  auto* values = vtkShortArray::SafeDownCast(image->GetPointData()->GetScalars());
  values->SetValue(0, 1234);
  vtkBaryImageIO::Write(image, path);
  EXPECT_EQ(vtkBaryImageIO::Read(path)->GetPointData()->GetScalars()->GetComponent(0, 0), 1234);
  EXPECT_EQ(ListFolder(dir), std::set<std::string>{ "label.mha" });
}
} // namespace
