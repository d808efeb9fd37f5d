#include "ScriptInspection.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
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

std::size_t skipSpaces(const std::string& text, std::size_t at)
{
  while (at < text.size() && std::isspace(static_cast<unsigned char>(text[at])))
  {
    ++at;
  }
  return at;
}

std::string lowered(std::string text)
{
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

// "# canopy-renders: yes|no" anywhere (case-insensitive, spaces optional), the first one wins.
// A hand scanner rather than std::regex: GCC 12's <regex> trips -Wmaybe-uninitialized under
// the sanitizer build's flags, and the words here are fixed.
Verdict overrideLine(const std::string& text)
{
  const std::string lower = lowered(text);
  static const std::string key = "canopy-renders";
  for (std::size_t hash = lower.find('#'); hash != std::string::npos;
       hash = lower.find('#', hash + 1))
  {
    std::size_t at = skipSpaces(lower, hash + 1);
    if (lower.compare(at, key.size(), key) != 0)
    {
      continue;
    }
    at = skipSpaces(lower, at + key.size());
    if (at >= lower.size() || lower[at] != ':')
    {
      continue;
    }
    at = skipSpaces(lower, at + 1);
    if (lower.compare(at, 3, "yes") == 0)
    {
      return Verdict::Renders;
    }
    if (lower.compare(at, 2, "no") == 0)
    {
      return Verdict::DoesNotRender;
    }
  }
  return Verdict::Unknown;
}

// Whether `name` occurs followed (after optional spaces) by "(" and returns the position
// after the parenthesis of the first such call through `after`.
bool findCall(const std::string& text, const std::string& name, std::size_t from,
              std::size_t& after)
{
  for (std::size_t at = text.find(name, from); at != std::string::npos;
       at = text.find(name, at + 1))
  {
    const std::size_t open = skipSpaces(text, at + name.size());
    if (open < text.size() && text[open] == '(')
    {
      after = open + 1;
      return true;
    }
  }
  return false;
}

bool createsImageExtractor(const std::string& text)
{
  static const char* const imageKinds[] = {"PNG", "JPG", "RecolorableImage", "CinemaVolumetricPNG"};
  std::size_t from = 0;
  std::size_t after = 0;
  while (findCall(text, "CreateExtractor", from, after))
  {
    const std::size_t quote = skipSpaces(text, after);
    if (quote < text.size() && (text[quote] == '\'' || text[quote] == '"'))
    {
      for (const char* kind : imageKinds)
      {
        const std::string quoted = std::string(kind) + text[quote];
        if (text.compare(quote + 1, quoted.size(), quoted) == 0)
        {
          return true;
        }
      }
    }
    from = after;
  }
  return false;
}

Verdict inspectSource(const std::string& text)
{
  const Verdict stated = overrideLine(text);
  if (stated != Verdict::Unknown)
  {
    return stated;
  }
  static const char* const renderingCalls[] = {"CreateView",       "GetActiveViewOrCreate",
                                               "CreateRenderView", "SaveScreenshot",
                                               "render_view",      "ImageScript"};
  std::size_t after = 0;
  for (const char* call : renderingCalls)
  {
    if (findCall(text, call, 0, after))
    {
      return Verdict::Renders;
    }
  }
  return createsImageExtractor(text) ? Verdict::Renders : Verdict::Unknown;
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
