#pragma once
// What the study's parts need for their markdown sections (oas_study.cpp, analytic_part.cpp):
// where and when they ran, and writing a section.
#include <string>

namespace oas::study {

/// The CPU's model name (/proc/cpuinfo), or "unknown CPU".
std::string cpuModel();

/// The current UTC date and time, "YYYY-MM-DD HH:MM UTC".
std::string today();

/// Writes a markdown section atomically (temp file, then rename), so an interrupted run leaves the
/// previous section whole.
void writeSection(const std::string& path, const std::string& text);

/// One more '#' on every heading line: a part's document becomes a section of STUDY.md.
std::string demoteHeadings(const std::string& text);

}  // namespace oas::study
