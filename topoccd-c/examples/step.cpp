// One CCD step between two mesh files, across a cut when a parents file is given: the C++
// wrapper. The same arguments and output as step.c:
//
//     step_cpp T0 T1 [PARENTS]
#include <topoccd.hpp>

#include <cstdio>
#include <iostream>

int main(int argc, char** argv) {
    if (argc < 3 || argc > 4) {
        std::cerr << "usage: " << argv[0] << " T0 T1 [PARENTS]\n";
        return 2;
    }
    try {
        topoccd::Frames frames = argc == 4 ? topoccd::Frames::read(argv[1], argv[2], argv[3])
                                           : topoccd::Frames::read(argv[1], argv[2]);
        for (const std::string& note : frames.notes()) std::cerr << "note: " << note << "\n";
        const std::uint32_t* face_origin = frames.face_origin();

        topoccd::Ccd ccd;
        topoccd::Report report = ccd.query(frames.step());
        std::printf("%zu contacts (%zu vf, %zu ee), earliest toi ", report.contact_count(),
                    report.vf().size(), report.ee().size());
        if (auto toi = report.earliest_toi())
            std::printf("%.17g\n", *toi);
        else
            std::printf("none\n");
        for (const topoccd_vf_contact& c : report.vf()) {
            std::printf("vf,%u,%u,%.17g", c.vertex, c.face, c.toi);
            if (face_origin != nullptr)
                std::printf(",%u,%u", face_origin[2 * c.face], face_origin[2 * c.face + 1]);
            std::printf("\n");
        }
        for (const topoccd_ee_contact& c : report.ee())
            std::printf("ee,%u,%u,%u,%u,%.17g\n", c.a[0], c.a[1], c.b[0], c.b[1], c.toi);
        if (report.unresolved() > 0)
            std::cerr << "warning: " << report.unresolved()
                      << " contacts unresolved (their times are lower bounds)\n";
    } catch (const topoccd::Error& e) {
        std::cerr << "error: " << e.what() << " (" << e.status_name() << ")\n";
        return 2;
    }
    return 0;
}
