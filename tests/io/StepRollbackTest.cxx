// canopy::io::StepRollback (adaptor/io/StepRollback.h) under HDF5, with the
// disk refusing writes from outside the code: the kernel's file-size limit
// (RLIMIT_FSIZE: writes past it fail with EFBIG). What must hold: HDF5 sees no
// failure (every call succeeds, the file closes), the rollback says what
// failed, and after undo() the file is byte for byte what it was before the
// step (or gone, if the step created it); the next step writes normally.
#include "StepRollback.h"

#include <gtest/gtest.h>

#include <hdf5.h>
#include <sys/resource.h>

#include <csignal>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numeric>
#include <string>
#include <vector>

namespace
{

using canopy::io::StepRollback;

std::string bytesOf(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// A file-size limit for the scope (SIGXFSZ ignored: the write fails with EFBIG).
class FileSizeLimit
{
public:
  explicit FileSizeLimit(rlim_t bytes)
  {
    getrlimit(RLIMIT_FSIZE, &this->Before);
    this->Handler = std::signal(SIGXFSZ, SIG_IGN);
    rlimit limit = this->Before;
    limit.rlim_cur = bytes;
    EXPECT_EQ(setrlimit(RLIMIT_FSIZE, &limit), 0);
  }
  ~FileSizeLimit()
  {
    setrlimit(RLIMIT_FSIZE, &this->Before);
    std::signal(SIGXFSZ, this->Handler);
  }
  FileSizeLimit(const FileSizeLimit&) = delete;
  FileSizeLimit& operator=(const FileSizeLimit&) = delete;

private:
  rlimit Before{};
  void (*Handler)(int) = nullptr;
};

/// A step: appends `values` to the 1D growing dataset "rows" (created with the
/// file when `create`), through `rollback`'s driver. Returns whether every
/// HDF5 call succeeded.
bool appendStep(StepRollback& rollback, const std::string& path, bool create,
                const std::vector<double>& values)
{
  const hid_t access = rollback.fileAccess();
  const hid_t file = create ? H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access)
                            : H5Fopen(path.c_str(), H5F_ACC_RDWR, access);
  H5Pclose(access);
  if (file < 0)
  {
    return false;
  }
  bool ok = true;
  hid_t dataset = H5I_INVALID_HID;
  if (create)
  {
    const hsize_t zero = 0, unlimited = H5S_UNLIMITED, chunk = 1024;
    const hid_t space = H5Screate_simple(1, &zero, &unlimited);
    const hid_t properties = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_chunk(properties, 1, &chunk);
    dataset = H5Dcreate2(file, "rows", H5T_IEEE_F64LE, space, H5P_DEFAULT, properties, H5P_DEFAULT);
    H5Pclose(properties);
    H5Sclose(space);
  }
  else
  {
    dataset = H5Dopen2(file, "rows", H5P_DEFAULT);
  }
  ok = dataset >= 0;
  if (ok)
  {
    const hid_t space = H5Dget_space(dataset);
    hsize_t rows = 0;
    H5Sget_simple_extent_dims(space, &rows, nullptr);
    H5Sclose(space);
    const hsize_t grown = rows + values.size(), count = values.size();
    ok = H5Dset_extent(dataset, &grown) >= 0;
    const hid_t fileSpace = H5Dget_space(dataset);
    const hid_t memory = H5Screate_simple(1, &count, nullptr);
    ok = ok && H5Sselect_hyperslab(fileSpace, H5S_SELECT_SET, &rows, nullptr, &count, nullptr) >= 0;
    ok = ok &&
         H5Dwrite(dataset, H5T_NATIVE_DOUBLE, memory, fileSpace, H5P_DEFAULT, values.data()) >= 0;
    H5Sclose(memory);
    H5Sclose(fileSpace);
    ok = H5Dclose(dataset) >= 0 && ok;
  }
  return H5Fclose(file) >= 0 && ok;
}

/// The dataset "rows" of `path`, read with HDF5's own default driver.
std::vector<double> readRows(const std::string& path)
{
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0)
  {
    return {};
  }
  const hid_t dataset = H5Dopen2(file, "rows", H5P_DEFAULT);
  const hid_t space = H5Dget_space(dataset);
  hsize_t rows = 0;
  H5Sget_simple_extent_dims(space, &rows, nullptr);
  std::vector<double> values(rows);
  H5Dread(dataset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
  H5Sclose(space);
  H5Dclose(dataset);
  H5Fclose(file);
  return values;
}

std::vector<double> ramp(std::size_t count, double start)
{
  std::vector<double> values(count);
  std::iota(values.begin(), values.end(), start);
  return values;
}

class StepRollbackTest : public ::testing::Test
{
protected:
  void SetUp() override
  {
    const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
    this->Folder = std::filesystem::temp_directory_path() /
                   ("canopy_step_rollback_" + std::string(test->name()));
    std::filesystem::remove_all(this->Folder);
    std::filesystem::create_directories(this->Folder);
    this->Path = (this->Folder / "rows.h5").string();
  }
  void TearDown() override { std::filesystem::remove_all(this->Folder); }

  std::filesystem::path Folder;
  std::string Path;
};

TEST_F(StepRollbackTest, KeptStepsAreReadableByHdf5sOwnDriver)
{
  StepRollback rollback(this->Path);
  ASSERT_EQ(rollback.begin(), "");
  ASSERT_TRUE(appendStep(rollback, this->Path, true, ramp(3000, 0)));
  EXPECT_FALSE(rollback.failed());
  ASSERT_EQ(rollback.keep(), "");
  ASSERT_EQ(rollback.begin(), "");
  ASSERT_TRUE(appendStep(rollback, this->Path, false, ramp(5000, 3000)));
  ASSERT_EQ(rollback.keep(), "");
  EXPECT_EQ(readRows(this->Path), ramp(8000, 0));
}

TEST_F(StepRollbackTest, UndoPutsBackEveryByteOfASucceededStep)
{
  StepRollback rollback(this->Path);
  ASSERT_EQ(rollback.begin(), "");
  ASSERT_TRUE(appendStep(rollback, this->Path, true, ramp(3000, 0)));
  ASSERT_EQ(rollback.keep(), "");
  const std::string before = bytesOf(this->Path);
  ASSERT_EQ(rollback.begin(), "");
  // A step that wrote well but that another rank failed: undone all the same.
  ASSERT_TRUE(appendStep(rollback, this->Path, false, ramp(5000, 3000)));
  EXPECT_NE(bytesOf(this->Path), before);
  EXPECT_GT(rollback.keptBytes(), 0u); // metadata of the first step was overwritten
  ASSERT_EQ(rollback.undo(), "");
  EXPECT_EQ(bytesOf(this->Path), before);
  EXPECT_EQ(readRows(this->Path), ramp(3000, 0));
}

TEST_F(StepRollbackTest, AFailedWriteIsHiddenFromHdf5AndUndone)
{
  StepRollback rollback(this->Path);
  ASSERT_EQ(rollback.begin(), "");
  ASSERT_TRUE(appendStep(rollback, this->Path, true, ramp(3000, 0)));
  ASSERT_EQ(rollback.keep(), "");
  const std::string before = bytesOf(this->Path);
  ASSERT_EQ(rollback.begin(), "");
  {
    // The disk refuses what lies 10 KB past the file's end: part of the step's
    // data goes, the rest and the metadata do not.
    const FileSizeLimit limit(before.size() + 10000);
    EXPECT_TRUE(appendStep(rollback, this->Path, false, ramp(50000, 3000)))
        << "HDF5 saw the failure";
  }
  ASSERT_TRUE(rollback.failed());
  EXPECT_NE(rollback.failure().find("File too large"), std::string::npos) << rollback.failure();
  const std::string kept = rollback.keep(); // a failed step is never kept
  EXPECT_NE(kept.find("File too large"), std::string::npos) << kept;
  EXPECT_EQ(bytesOf(this->Path), before);
  EXPECT_FALSE(rollback.undoOwed());
  // The disk is well again: the next step is written.
  ASSERT_EQ(rollback.begin(), "");
  ASSERT_TRUE(appendStep(rollback, this->Path, false, ramp(2000, 3000)));
  ASSERT_EQ(rollback.keep(), "");
  EXPECT_EQ(readRows(this->Path), ramp(5000, 0));
}

TEST_F(StepRollbackTest, AFailureAtTheFirstWriteLeavesTheFileAsItWas)
{
  StepRollback rollback(this->Path);
  ASSERT_EQ(rollback.begin(), "");
  ASSERT_TRUE(appendStep(rollback, this->Path, true, ramp(100, 0)));
  ASSERT_EQ(rollback.keep(), "");
  const std::string before = bytesOf(this->Path);
  ASSERT_EQ(rollback.begin(), "");
  {
    // Nothing past the end: the first write that grows the file fails.
    const FileSizeLimit limit(before.size());
    EXPECT_TRUE(appendStep(rollback, this->Path, false, ramp(20000, 100)));
  }
  ASSERT_TRUE(rollback.failed());
  ASSERT_EQ(rollback.undo(), "");
  EXPECT_EQ(bytesOf(this->Path), before);
  EXPECT_EQ(readRows(this->Path), ramp(100, 0));
}

TEST_F(StepRollbackTest, AFailedFirstStepLeavesNoFile)
{
  StepRollback rollback(this->Path);
  ASSERT_EQ(rollback.begin(), "");
  {
    const FileSizeLimit limit(3000);
    EXPECT_TRUE(appendStep(rollback, this->Path, true, ramp(20000, 0)));
  }
  ASSERT_TRUE(rollback.failed());
  ASSERT_EQ(rollback.undo(), "");
  EXPECT_FALSE(std::filesystem::exists(this->Path));
}

TEST_F(StepRollbackTest, AStepThatNeverOpenedTheFileHasNothingToUndo)
{
  StepRollback rollback((this->Folder / "missing" / "rows.h5").string());
  ASSERT_EQ(rollback.begin(), "");
  const hid_t access = rollback.fileAccess();
  H5E_BEGIN_TRY
  {
    EXPECT_LT(H5Fopen((this->Folder / "missing" / "rows.h5").c_str(), H5F_ACC_RDWR, access), 0);
  }
  H5E_END_TRY;
  H5Pclose(access);
  EXPECT_EQ(rollback.undo(), "");
  EXPECT_FALSE(rollback.undoOwed());
  EXPECT_EQ(rollback.begin(), "");
}

} // namespace
