/* canopy/canopy.h compiled as C (C99, no extensions): the C API's header must
 * not need C++, and a C program links Canopy::adaptor as it is. */
#include <canopy/canopy.h>

#include <stddef.h>

int main(void)
{
  canopy_options* options = NULL;
  const int ok = canopy_options_create(&options) == CANOPY_OK && options != NULL;
  canopy_options_destroy(options);
  return ok ? 0 : 1;
}
