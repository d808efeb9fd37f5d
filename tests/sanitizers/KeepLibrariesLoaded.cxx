// Sanitizer builds only (CANOPY_SANITIZE, see the top-level CMakeLists.txt):
// dlclose leaves every library loaded. LeakSanitizer looks for leaks at exit,
// after MPI_Finalize has unloaded OpenMPI's components; their allocations would
// print as "<unknown module>", which no suppression can name. Defined in
// libcanopy_forest, which every Canopy program loads before the C library, so it
// takes the place of the C library's dlclose for the whole process.
extern "C" int dlclose(void* /*handle*/)
{
  return 0;
}
