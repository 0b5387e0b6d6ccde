// Python bindings: to be written by the Python helper.
