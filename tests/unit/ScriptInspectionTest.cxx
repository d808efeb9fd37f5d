// canopy::scriptRenders: which Catalyst scripts need a display, read from their text
// (the shipped pipelines and what a user's script may look like), and the override line.
#include "ScriptInspection.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace fs = std::filesystem;

namespace
{

class ScriptInspection : public ::testing::Test
{
protected:
  void SetUp() override
  {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    Scratch = fs::temp_directory_path() /
              ("canopy_script_inspection_" + std::to_string(getpid()) + "_" + info->name());
    fs::remove_all(Scratch);
    fs::create_directories(Scratch);
  }
  void TearDown() override { fs::remove_all(Scratch); }

  std::string script(const std::string& name, const std::string& text)
  {
    const fs::path path = Scratch / name;
    fs::create_directories(path.parent_path());
    std::ofstream(path) << text;
    return path.string();
  }

  fs::path Scratch;
};

TEST_F(ScriptInspection, ViewsAndScreenshotsRender)
{
  EXPECT_TRUE(canopy::scriptRenders(script("a.py", "view = CreateView('RenderView')\n")));
  EXPECT_TRUE(canopy::scriptRenders(script("b.py", "v = GetActiveViewOrCreate ('RenderView')\n")));
  EXPECT_TRUE(canopy::scriptRenders(script("c.py", "SaveScreenshot(\n  'x.png')\n")));
  EXPECT_TRUE(canopy::scriptRenders(script("d.py", "canopy_catalyst.render_view(src)\n")));
  EXPECT_TRUE(canopy::scriptRenders(script("e.py", "script = ImageScript(args)\n")));
  EXPECT_TRUE(canopy::scriptRenders(script("f.py", "v = CreateRenderView()\n")));
}

TEST_F(ScriptInspection, ImageExtractorsRenderDataExtractorsDoNot)
{
  EXPECT_TRUE(canopy::scriptRenders(script("png.py", "CreateExtractor('PNG', view)\n")));
  EXPECT_TRUE(canopy::scriptRenders(script("jpg.py", "CreateExtractor( \"JPG\", view)\n")));
  EXPECT_TRUE(canopy::scriptRenders(
      script("cinema.py", "x = CreateExtractor('CinemaVolumetricPNG', view)\n")));
  EXPECT_FALSE(canopy::scriptRenders(script("vtpd.py", "CreateExtractor('VTPD', source)\n")));
  // A name the image kind merely starts is not that kind.
  EXPECT_FALSE(canopy::scriptRenders(script("pngx.py", "CreateExtractor('PNGX', source)\n")));
  // A word without its call is not a call.
  EXPECT_FALSE(canopy::scriptRenders(script("word.py", "# SaveScreenshot is not used here\n")));
  EXPECT_FALSE(canopy::scriptRenders(script("plain.py", "x = 1\n")));
}

TEST_F(ScriptInspection, TheOverrideLineWins)
{
  EXPECT_FALSE(canopy::scriptRenders(
      script("no.py", "#  Canopy-Renders :  NO\nview = CreateView('RenderView')\n")));
  EXPECT_TRUE(canopy::scriptRenders(script("yes.py", "x = 1\n# canopy-renders: yes\n")));
  // A malformed override is no override: the guess stands.
  EXPECT_TRUE(canopy::scriptRenders(
      script("bad.py", "# canopy-renders maybe\nview = CreateView('RenderView')\n")));
}

TEST_F(ScriptInspection, APackageRendersIfAnyModuleDoesUnlessOneSaysNo)
{
  const fs::path package = Scratch / "pkg";
  script("pkg/__init__.py", "from . import views\n");
  script("pkg/views.py", "SaveScreenshot('x.png')\n");
  EXPECT_TRUE(canopy::scriptRenders(package.string()));
  script("pkg/policy.py", "# canopy-renders: no\n");
  EXPECT_FALSE(canopy::scriptRenders(package.string()));
}

} // namespace
