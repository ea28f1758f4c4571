/* What every public header shares: the marks of the public API (docs/api.md).
 *  - BF_API marks a function or object of the public API: exported from the shared
 *    library (which hides everything else) and callable from C and C++.
 *  - BF_DEPRECATED("use bf_x") marks one that will be removed at the next ABI break: it
 *    still works, and compilers warn where it is used, naming what replaces it. */
#ifndef BRDFIT_API_H
#define BRDFIT_API_H

#if defined(__GNUC__) || defined(__clang__)
#define BF_API __attribute__((visibility("default")))
#define BF_DEPRECATED(replacement) __attribute__((deprecated(replacement)))
#else
#define BF_API
#define BF_DEPRECATED(replacement)
#endif

#endif
