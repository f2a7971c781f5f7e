/* Preloaded by scripts/sanitize into every test program: dlclose() keeps the
 * library loaded, so that LeakSanitizer, which looks at exit, can still name
 * the library of a leak made by a plugin that is unloaded before then (the GL
 * driver VTK loads through GLX; tests/sanitize/lsan.supp). Never in RoverLab. */
int dlclose(void* handle) {
  (void)handle;
  return 0;
}
