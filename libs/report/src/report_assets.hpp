#pragma once
// The HTML report's fixed parts, kept as real files in libs/report/assets/
// and embedded at build time (cmake/icrkitEmbedFiles.cmake writes each file's
// bytes as a NUL-terminated array), so that the page needs nothing at run time.

namespace icrkit::report {

/// assets/report.css: the page's style sheet.
extern const char kReportCss[];
/// assets/report_status.js: installed first, so that every error of the
/// page, three.js's console.error messages included, is visible to a test
/// through #report-status.
extern const char kReportStatusJs[];
/// assets/report_viewer.js: the 3D viewer. three.js is an ES module only
/// (r160+), and a page opened from disk may not load module files; so the
/// vendored module text becomes a Blob URL, OrbitControls' `from 'three'` is
/// pointed at it, and both are imported dynamically. Nothing leaves the page.
extern const char kReportViewerJs[];

}  // namespace icrkit::report
