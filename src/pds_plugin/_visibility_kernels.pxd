from libc.stdint cimport int64_t

cdef struct Chords:
    # the chords of a ``vis`` bundle (see _visibility_kernels.pyx), as raw pointers into
    # the bundle's arrays (the caller keeps the bundle alive)
    const double *xy            # (m, 2, 2): chord e runs from xy[e, 0] to xy[e, 1]
    const int64_t *prev         # (m,): the chord before chord e along its ring
    const int64_t *out          # (n,): each point's outgoing chord, -1 if none
    const int64_t *start        # CSR lists of the chords near each grid cell
    const int64_t *items
    double x0, y0, h
    Py_ssize_t nx, ny
    bint empty                  # no chords: every point sees every point

cdef Chords chords_of(tuple vis) except *
cdef int orient_sign(double ax, double ay, double bx, double by, double cx,
                     double cy) noexcept nogil
cdef bint near_boundary(double x, double y, const Chords *c) noexcept nogil
cdef bint sees(double ax, double ay, Py_ssize_t a_out, double bx, double by, Py_ssize_t b_out,
               const Chords *c) noexcept nogil
cdef bint box_seen(double px, double py, Py_ssize_t p_out, double bx, double by, double size,
                   double tol, const Chords *c) noexcept nogil
