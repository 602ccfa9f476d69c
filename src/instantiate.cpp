// Explicit instantiations of the float and double trees live here (see extern templates in the headers).
