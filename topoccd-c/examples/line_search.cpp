// A simulator's line search over a frame sequence: the C++ wrapper (Ccd::collision_free_stepsize),
// with Eigen when it is on the include path. The same arguments and output as line_search.c:
//
//     line_search_cpp SEQ_DIR
//
// With Eigen, each step is also cut short where the line search stops: the positions at
// alpha = 0.8 t are x(alpha) = x0 + alpha (x1 - x0), computed on row-major Eigen matrices
// and given to the query in place; the shortened step must be free of contacts, and a line
// "  the step to ALPHA: N contacts" says so.
#include <topoccd.hpp>

#include <cstdio>
#include <iostream>

#if defined(TOPOCCD_HAS_EIGEN)
using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

// The contacts of the step from x0 to x0 + alpha (x1 - x0), across the same topology change.
static std::size_t shortened_contacts(topoccd::Ccd& ccd, const topoccd_step& s, double alpha) {
    Eigen::Map<const RowMatrix> x0(s.x0, static_cast<Eigen::Index>(s.x0_count), 3);
    Eigen::Map<const RowMatrix> x1(s.x1, static_cast<Eigen::Index>(s.x1_count), 3);
    RowMatrix start = x1;  // a new vertex without a parent does not move
    start.topRows(x0.rows()) = x0;
    for (std::size_t i = 0; i < s.parent_count; i++) {
        std::uint32_t child = s.parents[2 * i], parent = s.parents[2 * i + 1];
        if (child >= s.x0_count) start.row(child) = x0.row(parent);  // starts at its parent
    }
    RowMatrix end = start + alpha * (x1 - start);
    // The new vertices start at their parents: x0 holds the old ones only, as the library
    // requires with parents (it places each child at its parent).
    RowMatrix old = start.topRows(x0.rows());
    topoccd::Step shortened(old, end, topoccd::Indices(s.triangles, s.triangle_count));
    if (s.parents != nullptr) shortened.parents(topoccd::ParentRows(s.parents, s.parent_count));
    return ccd.query(shortened).contact_count();
}
#endif

int main(int argc, char** argv) {
    if (argc != 2) {
        std::cerr << "usage: " << argv[0] << " SEQ_DIR\n";
        return 2;
    }
    try {
        topoccd::Sequence seq = topoccd::Sequence::open(argv[1]);
        topoccd::Ccd ccd;  // one for every step: its buffers are reused
        topoccd::LineSearchOptions options;
        // options.check_start(true) would refuse a step whose start has intersecting
        // triangles: the generated sequences have such frames by design.
        options.conservative_rescaling(0.8);
        int exit_code = 0;
        for (std::size_t k = 0; k < seq.steps(); k++) {
            topoccd::Frames frames = seq.load(k);
            topoccd::Step step = frames.step();  // kept: step.c() refers into it
            topoccd::StepSize size = ccd.collision_free_stepsize(step, options);
            std::optional<double> toi = size.report.earliest_toi();
            double alpha = size.alpha;
            if (toi)
                std::printf("step %zu: earliest toi %.17g (%zu vf, %zu ee), take %.17g of the step\n",
                            k, *toi, size.report.vf().size(), size.report.ee().size(), alpha);
            else
                std::printf("step %zu: earliest toi none (0 vf, 0 ee), take %.17g of the step\n",
                            k, alpha);
            if (const topoccd_vf_contact* c = size.report.earliest_vf())
                std::printf("  earliest: vertex %u, face %u\n", c->vertex, c->face);
            if (const topoccd_ee_contact* c = size.report.earliest_ee())
                std::printf("  earliest: edge %u-%u, edge %u-%u\n", c->a[0], c->a[1], c->b[0],
                            c->b[1]);
#if defined(TOPOCCD_HAS_EIGEN)
            std::size_t contacts = shortened_contacts(ccd, step.c(), alpha);
            std::printf("  the step to %.17g: %zu contacts\n", alpha, contacts);
            if (contacts != 0 && toi) exit_code = 1;  // the line search would not be safe
#endif
        }
        return exit_code;
    } catch (const topoccd::Error& e) {
        std::cerr << "error: " << e.what() << " (" << e.status_name() << ")\n";
        return 2;
    }
}
