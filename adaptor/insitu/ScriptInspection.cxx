#include "ScriptInspection.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

namespace canopy
{
namespace
{

enum class Verdict
{
  Renders,
  DoesNotRender,
  Unknown
};

Verdict inspectSource(const std::string& text)
{
  static const std::regex overrideLine(R"(#\s*canopy-renders\s*:\s*(yes|no))", std::regex::icase);
  std::smatch match;
  if (std::regex_search(text, match, overrideLine))
  {
    std::string answer = match[1].str();
    std::transform(answer.begin(), answer.end(), answer.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return answer == "no" ? Verdict::DoesNotRender : Verdict::Renders;
  }
  static const std::regex renderingCall(
      R"((CreateView|GetActiveViewOrCreate|CreateRenderView|SaveScreenshot|render_view|ImageScript)\s*\()"
      R"(|CreateExtractor\s*\(\s*['"](PNG|JPG|RecolorableImage|CinemaVolumetricPNG)['"])");
  return std::regex_search(text, renderingCall) ? Verdict::Renders : Verdict::Unknown;
}

std::string readText(const std::filesystem::path& path)
{
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

} // namespace

bool scriptRenders(const std::string& path)
{
  namespace fs = std::filesystem;
  std::error_code error;
  if (fs::is_directory(path, error))
  {
    bool renders = false;
    for (fs::recursive_directory_iterator it(path, error), end; !error && it != end;
         it.increment(error))
    {
      const auto& entry = *it;
      if (entry.path().extension() == ".py")
      {
        const Verdict verdict = inspectSource(readText(entry.path()));
        if (verdict == Verdict::DoesNotRender)
        {
          return false;
        }
        renders = renders || verdict == Verdict::Renders;
      }
    }
    return renders;
  }
  if (fs::path(path).extension() == ".zip")
  {
    return true;
  }
  return inspectSource(readText(path)) == Verdict::Renders;
}

bool scriptReadable(const std::string& path, std::string& why)
{
  namespace fs = std::filesystem;
  std::error_code error;
  if (!fs::exists(path, error))
  {
    why = "no such file or directory";
    return false;
  }
  if (fs::is_directory(path, error))
  {
    return true;
  }
  std::ifstream in(path);
  if (!in)
  {
    why = "cannot be read";
    return false;
  }
  return true;
}

} // namespace canopy
