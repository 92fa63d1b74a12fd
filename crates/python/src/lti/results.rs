//! The small result classes of the LTI functions: frozen, with named attributes (NumPy arrays
//! and numbers), and the sequence protocol over python-control's tuple, so that
//! `K, S, E = pendulab.lqr(A, B, Q, R)` unpacks as in python-control while `res.residual`
//! carries the diagnostics. Classes that stand for one matrix (e.g. `lyap`'s solution) also
//! implement `__array__`, so NumPy functions accept them directly.

use pyo3::prelude::*;

/// `value` as a Python object (numbers, strings, arrays alike).
pub fn obj<'py, T: pyo3::IntoPyObjectExt<'py>>(py: Python<'py>, value: T) -> PyResult<Py<PyAny>> {
    Ok(value.into_bound_py_any(py)?.unbind())
}

/// Declares a result class: `result_class!(Rust name, "PythonName", "doc", array
/// field-or-none, unpack { field as "attr": "doc", … } also { field as "attr": "doc", … })`.
/// The `unpack` fields, in order, are python-control's tuple; the `also` fields are further
/// attributes. Every field holds a Python object.
macro_rules! result_class {
    (
        $name:ident, $pyname:literal, $doc:literal,
        array $arr:tt,
        unpack { $( $u:ident as $uname:literal : $udoc:literal ),* $(,)? }
        also { $( $a:ident as $aname:literal : $adoc:literal ),* $(,)? }
    ) => {
        result_class!(
            @class $name, $pyname, $doc, [$($u),*], $arr,
            { $($u as $uname: $udoc,)* $($a as $aname: $adoc,)* }
        );
    };
    (
        @class $name:ident, $pyname:literal, $doc:literal,
        [$($u:ident),*],
        $arr:tt,
        { $( $f:ident as $fname:literal : $fdoc:literal ),* $(,)? }
    ) => {
        #[doc = $doc]
        #[pyclass(name = $pyname, module = "pendulab", frozen)]
        pub struct $name {
            $( #[doc = $fdoc] pub $f: Py<PyAny>, )*
        }

        #[pymethods]
        impl $name {
            $(
                #[doc = $fdoc]
                #[getter($fname)]
                fn $f(&self, py: Python<'_>) -> Py<PyAny> {
                    self.$f.clone_ref(py)
                }
            )*

            fn __iter__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyIterator>> {
                self.unpacked(py)?.into_any().try_iter()
            }

            fn __len__(&self) -> usize {
                [$(stringify!($u)),*].len()
            }

            fn __getitem__(&self, py: Python<'_>, index: isize) -> PyResult<Py<PyAny>> {
                Ok(self.unpacked(py)?.into_any().get_item(index)?.unbind())
            }

            /// The array this result stands for (`numpy.asarray(result)`); results that
            /// stand for several values raise `TypeError` (unpack them instead).
            #[pyo3(signature = (dtype = None, copy = None))]
            fn __array__(
                &self,
                py: Python<'_>,
                dtype: Option<Bound<'_, PyAny>>,
                copy: Option<bool>,
            ) -> PyResult<Py<PyAny>> {
                let array: Option<&Py<PyAny>> = result_class!(@array self, $arr);
                let Some(value) = array else {
                    return Err(pyo3::exceptions::PyTypeError::new_err(concat!(
                        $pyname,
                        " holds several values: unpack it or use its attributes"
                    )));
                };
                let value = value.bind(py);
                let out = match (dtype, copy) {
                    (None, Some(true)) => value.call_method0("copy")?,
                    (None, _) => value.clone(),
                    (Some(dt), _) => py.import("numpy")?.getattr("asarray")?.call1((value, dt))?,
                };
                Ok(out.unbind())
            }

            fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
                let mut parts: Vec<String> = Vec::new();
                $( parts.push(format!("{}={}", $fname, self.$f.bind(py).repr()?)); )*
                Ok(format!("{}({})", $pyname, parts.join(", ")))
            }

        }

        impl $name {
            /// The python-control tuple this result unpacks to.
            fn unpacked<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyTuple>> {
                pyo3::types::PyTuple::new(py, [$(self.$u.clone_ref(py)),*])
            }
        }
    };
    (@array $self:ident, none) => {
        None
    };
    (@array $self:ident, $field:ident) => {
        Some(&$self.$field)
    };
}
pub(crate) use result_class;
