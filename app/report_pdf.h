#pragma once
// The report as PDF (`roverlab report --pdf`): the HTML page printed by
// Debian's headless Chromium, which draws it as a browser shows it (the
// inline SVG plots, the CSS, the PNG views), A4, no header or footer.

#include <string>

namespace roverlab::app {

// The browser that prints it; throws EnvironmentError when there is none
// (called before the report is made, so the user learns at once).
std::string report_pdf_printer();

// Prints `html_file` (its pictures beside it) to `pdf_file`, atomically, with
// the mode the umask gives. Throws EnvironmentError when chromium is missing
// and InputError naming `pdf_file` when printing fails or times out.
void print_report_pdf(const std::string& html_file, const std::string& pdf_file);

}  // namespace roverlab::app
