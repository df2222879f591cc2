// Reply builders.
#include "http.hpp"

#include "api/json_text.hpp"
#include "api/utf8.hpp"

#include <boost/json.hpp>

namespace wiredem::server {

StringResponse text_response(const Request& req, http::status status, std::string body,
    std::string_view content_type)
{
    StringResponse res{status, req.version()};
    res.set(http::field::server, server_name);
    res.set(http::field::content_type, content_type);
    res.set(http::field::cache_control, "no-store");
    res.keep_alive(req.keep_alive());
    res.body() = std::move(body);
    res.prepare_payload();
    return res;
}

StringResponse no_content_response(const Request& req)
{
    StringResponse res{http::status::no_content, req.version()};
    res.set(http::field::server, server_name);
    res.keep_alive(req.keep_alive());
    return res;
}

StringResponse json_response(const Request& req, http::status status, const boost::json::value& body)
{
    std::string text = api::json_document_text(body);
    text.push_back('\n');
    return text_response(req, status, std::move(text), "application/json");
}

StringResponse error_response(const Request& req, http::status status, std::string_view code,
    std::string_view message, std::string_view field, const std::vector<FieldProblem>& details)
{
    // The message and the field may echo what the client sent (a Host
    // header, a decoded query parameter, a path), which need not be UTF-8; a
    // JSON text must be (RFC 8259 §8.1), and Boost.JSON writes strings
    // unchecked. Each is bounded (api::bounded_echo), and so is the number of
    // details: a hostile request of a megabyte gets a reply of kilobytes.
    boost::json::object err;
    err["code"] = code;
    err["message"] = api::bounded_echo(message, max_error_message_bytes);
    err["field"] = field.empty() ? boost::json::value(nullptr)
                                 : boost::json::value(api::bounded_echo(field, max_error_field_bytes));
    if (!details.empty()) {
        boost::json::array list;
        for (std::size_t k = 0; k < details.size() && k < max_error_details; ++k)
            list.push_back(boost::json::object{{"field", api::bounded_echo(details[k].field, max_error_field_bytes)},
                {"message", api::bounded_echo(details[k].message, max_error_message_bytes)}});
        if (details.size() > max_error_details)
            list.push_back(boost::json::object{{"field", nullptr},
                {"message", "and " + std::to_string(details.size() - max_error_details) + " more problems"}});
        err["details"] = std::move(list);
    }
    return json_response(req, status, boost::json::object{{"error", std::move(err)}});
}

unsigned status_of(const Response& res)
{
    return std::visit([](const auto& r) { return r.result_int(); }, res);
}

} // namespace wiredem::server
