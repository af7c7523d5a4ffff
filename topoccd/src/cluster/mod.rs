//! Dynamic clustering (section 4 of the paper): leaf clusters grown around observation points,
//! intermediate clusters merged from them.
