from libc.stdint cimport int64_t

cdef struct ConeTree:
    # a ``build_cone_tree`` tree of features (see _sizing_kernels.pyx) with their sizes,
    # as raw pointers into its arrays (the caller keeps them alive)
    const double *xy            # (m, 2) features
    const double *s             # (m,) sizes
    const int64_t *perm
    const int64_t *first
    const int64_t *stop
    const int64_t *left
    const int64_t *right
    const double *box           # (nodes, 4)
    const double *smin
    double L, cap

cdef ConeTree cone_tree_of(features, sizes, double L, double cap, tuple tree) except *
cdef double cone_at(const ConeTree *t, double x, double y, double best, int64_t *stack,
                    double *bound) noexcept nogil
cdef void quarters_at(const ConeTree *t, double x_lo, double y_lo, double size, double *best,
                      int64_t *stack) noexcept nogil

cdef enum:
    CONE_STACK = 256    # the stack a search needs at most (twice the tree's depth)
