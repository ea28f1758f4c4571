# Types of the compiled cffi module (brdfit/_build.py makes it): the C declarations are
# checked by the C compiler there, so here they are Any; what Python code relies on from
# the ffi object itself is typed.
from typing import Any, Callable, TypeVar

_F = TypeVar("_F", bound=Callable[..., Any])

class _FFI:
    NULL: Any
    def def_extern(self, name: str = ..., error: Any = ..., onerror: Any = ...) -> Callable[[_F], _F]: ...
    def __getattr__(self, name: str) -> Any: ...

ffi: _FFI
lib: Any
