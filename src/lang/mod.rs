//! Text to scene graph: the pest grammar, expression evaluation, `#declare` and `#include`.
