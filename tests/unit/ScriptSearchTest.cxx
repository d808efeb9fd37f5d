// canopy::findScript: the order in which a pipeline script's path is looked
// for (absolute as given; relative: working directory, CANOPY_PIPELINES_DIR,
// shipped pipelines) and what a failed search reports. Each test runs in a
// scratch directory it makes its working directory.
#include "ScriptSearch.h"
#include "RuntimePaths.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace
{

class ScriptSearch : public ::testing::Test
{
protected:
  void SetUp() override
  {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    Scratch = fs::temp_directory_path() /
              ("canopy_script_search_" + std::to_string(getpid()) + "_" + info->name());
    fs::remove_all(Scratch);
    fs::create_directories(Scratch / "cwd");
    fs::create_directories(Scratch / "alternate");
    Previous = fs::current_path();
    fs::current_path(Scratch / "cwd");
    unsetenv("CANOPY_PIPELINES_DIR");
  }
  void TearDown() override
  {
    unsetenv("CANOPY_PIPELINES_DIR");
    fs::current_path(Previous);
    fs::remove_all(Scratch);
  }
  static void touch(const fs::path& file) { std::ofstream(file) << "# script-version: 2\n"; }
  std::string shipped(const std::string& name) const
  {
    return (fs::path(canopy::shippedPipelinesDirectory()) / name).lexically_normal().string();
  }

  fs::path Scratch;
  fs::path Previous;
};

TEST_F(ScriptSearch, ShippedPipelinesHoldTheScripts)
{
  // The build tree's fallback is the source tree's pipelines/: the bare names work.
  EXPECT_TRUE(fs::exists(shipped("surface_image.py")));
  EXPECT_TRUE(fs::exists(shipped("canopy_catalyst.py")));
}

TEST_F(ScriptSearch, AbsolutePathAsGiven)
{
  touch(Scratch / "alternate" / "surface_image.py");
  setenv("CANOPY_PIPELINES_DIR", (Scratch / "alternate").c_str(), 1);
  const auto location = canopy::findScript(shipped("surface_image.py"));
  EXPECT_EQ(location.path, shipped("surface_image.py"));
  EXPECT_EQ(location.searched, std::vector<std::string>{shipped("surface_image.py")});
}

TEST_F(ScriptSearch, MissingAbsolutePathLooksNowhereElse)
{
  const std::string missing = (Scratch / "cwd" / "surface_image.py").string();
  const auto location = canopy::findScript(missing);
  EXPECT_FALSE(location.found());
  EXPECT_EQ(location.searched, std::vector<std::string>{missing});
  EXPECT_EQ(location.notFoundReason(), "no such file or directory");
}

TEST_F(ScriptSearch, WorkingDirectoryFirst)
{
  touch(Scratch / "cwd" / "surface_image.py");
  touch(Scratch / "alternate" / "surface_image.py");
  setenv("CANOPY_PIPELINES_DIR", (Scratch / "alternate").c_str(), 1);
  EXPECT_EQ(canopy::findScript("surface_image.py").path,
            (Scratch / "cwd" / "surface_image.py").string());
}

TEST_F(ScriptSearch, EnvironmentBeforeShipped)
{
  touch(Scratch / "alternate" / "surface_image.py");
  setenv("CANOPY_PIPELINES_DIR", (Scratch / "alternate").c_str(), 1);
  const auto location = canopy::findScript("surface_image.py");
  EXPECT_EQ(location.path, (Scratch / "alternate" / "surface_image.py").string());
  EXPECT_EQ(location.searched.size(), 2u);
}

TEST_F(ScriptSearch, RelativeEnvironmentCountsFromWorkingDirectory)
{
  fs::create_directories(Scratch / "cwd" / "mine");
  touch(Scratch / "cwd" / "mine" / "selection_extract.py");
  setenv("CANOPY_PIPELINES_DIR", "mine", 1);
  EXPECT_EQ(canopy::findScript("selection_extract.py").path,
            (Scratch / "cwd" / "mine" / "selection_extract.py").string());
}

TEST_F(ScriptSearch, ShippedLast)
{
  setenv("CANOPY_PIPELINES_DIR", (Scratch / "alternate").c_str(), 1);
  EXPECT_EQ(canopy::findScript("selection_extract.py").path, shipped("selection_extract.py"));
  unsetenv("CANOPY_PIPELINES_DIR");
  EXPECT_EQ(canopy::findScript("./selection_extract.py").path, shipped("selection_extract.py"));
}

TEST_F(ScriptSearch, PackageDirectoryIsFound)
{
  fs::create_directories(Scratch / "alternate" / "my_pipeline");
  setenv("CANOPY_PIPELINES_DIR", (Scratch / "alternate").c_str(), 1);
  EXPECT_EQ(canopy::findScript("my_pipeline").path,
            (Scratch / "alternate" / "my_pipeline").string());
}

TEST_F(ScriptSearch, NotFoundListsEveryPlaceInOrder)
{
  setenv("CANOPY_PIPELINES_DIR", (Scratch / "alternate").c_str(), 1);
  const auto location = canopy::findScript("no_such.py");
  const std::vector<std::string> places{(Scratch / "cwd" / "no_such.py").string(),
                                        (Scratch / "alternate" / "no_such.py").string(),
                                        shipped("no_such.py")};
  EXPECT_FALSE(location.found());
  EXPECT_EQ(location.searched, places);
  EXPECT_EQ(location.notFoundReason(), "no such file or directory; looked for " + places[0] + ", " +
                                           places[1] + ", " + places[2]);
}

TEST_F(ScriptSearch, EmptyEnvironmentIsIgnored)
{
  setenv("CANOPY_PIPELINES_DIR", "", 1);
  EXPECT_EQ(canopy::findScript("no_such.py").searched.size(), 2u);
}

TEST_F(ScriptSearch, EmptyPathIsNotTheWorkingDirectory)
{
  const auto location = canopy::findScript("");
  EXPECT_FALSE(location.found());
  EXPECT_EQ(location.notFoundReason(), "the path is empty");
}

} // namespace
